#pragma once
// Any EliteArchive (archive.hpp) behind one type, so that a config can choose an archive at run
// time (`[archive] kind`, plugin/part_registries.hpp) and MAP-Elites run it: BasicMapElites<
// AnyArchive> calls each member through one virtual call. The built-in grid is not wrapped: its
// MAP-Elites calls it directly. AnyArchive models EliteArchive itself.
#include <concepts>
#include <memory>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "qdmeta/archive/archive.hpp"

namespace qdmeta {

class AnyArchive {
 public:
  template <class A>
    requires(!std::same_as<std::remove_cvref_t<A>, AnyArchive>) && EliteArchive<std::remove_cvref_t<A>>
  explicit AnyArchive(A&& archive)
      : impl_(std::make_unique<Model<std::remove_cvref_t<A>>>(std::forward<A>(archive))) {}

  Index cells() const { return impl_->cells(); }
  Index dimensions() const { return impl_->dimensions(); }
  Index size() const { return impl_->size(); }
  bool empty() const { return impl_->empty(); }
  Index solution_size() const { return impl_->solution_size(); }
  Index base_feature_size() const { return impl_->base_feature_size(); }
  Index sample_cell(Rng& rng) const { return impl_->sample_cell(rng); }
  const Real* solution(Index cell) const { return impl_->solution(cell); }
  Real objective(Index cell) const { return impl_->objective(cell); }
  const std::vector<Index>& filled_cells() const { return impl_->filled_cells(); }
  ArchiveStats stats() const { return impl_->stats(); }
  EliteTable elites() const { return impl_->elites(); }
  Index add_batch(const EliteBatch& batch, std::span<AddStatus> status = {}) { return impl_->add_batch(batch, status); }
  void clear() { impl_->clear(); }
  void save(BinaryWriter& out) const { impl_->save(out); }
  void load(BinaryReader& in) { impl_->load(in); }

  // The archive inside when it is an A, else nullptr.
  template <class A>
  const A* get() const {
    const auto* model = dynamic_cast<const Model<A>*>(impl_.get());
    return model ? &model->archive : nullptr;
  }

 private:
  struct Interface {
    virtual ~Interface() = default;
    virtual Index cells() const = 0;
    virtual Index dimensions() const = 0;
    virtual Index size() const = 0;
    virtual bool empty() const = 0;
    virtual Index solution_size() const = 0;
    virtual Index base_feature_size() const = 0;
    virtual Index sample_cell(Rng& rng) const = 0;
    virtual const Real* solution(Index cell) const = 0;
    virtual Real objective(Index cell) const = 0;
    virtual const std::vector<Index>& filled_cells() const = 0;
    virtual ArchiveStats stats() const = 0;
    virtual EliteTable elites() const = 0;
    virtual Index add_batch(const EliteBatch& batch, std::span<AddStatus> status) = 0;
    virtual void clear() = 0;
    virtual void save(BinaryWriter& out) const = 0;
    virtual void load(BinaryReader& in) = 0;
  };
  template <class A>
  struct Model final : Interface {
    template <class Arg>
    explicit Model(Arg&& a) : archive(std::forward<Arg>(a)) {}
    Index cells() const override { return archive.cells(); }
    Index dimensions() const override { return archive.dimensions(); }
    Index size() const override { return archive.size(); }
    bool empty() const override { return archive.empty(); }
    Index solution_size() const override { return archive.solution_size(); }
    Index base_feature_size() const override { return archive.base_feature_size(); }
    Index sample_cell(Rng& rng) const override { return archive.sample_cell(rng); }
    const Real* solution(Index cell) const override { return archive.solution(cell); }
    Real objective(Index cell) const override { return archive.objective(cell); }
    const std::vector<Index>& filled_cells() const override { return archive.filled_cells(); }
    ArchiveStats stats() const override { return archive.stats(); }
    EliteTable elites() const override { return archive.elites(); }
    Index add_batch(const EliteBatch& batch, std::span<AddStatus> status) override {
      return archive.add_batch(batch, status);
    }
    void clear() override { archive.clear(); }
    void save(BinaryWriter& out) const override { archive.save(out); }
    void load(BinaryReader& in) override { archive.load(in); }
    A archive;
  };
  std::unique_ptr<Interface> impl_;
};

static_assert(EliteArchive<AnyArchive>);

}  // namespace qdmeta
