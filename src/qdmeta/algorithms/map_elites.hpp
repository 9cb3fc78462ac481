#pragma once
// Plain MAP-Elites (docs/specification.md, MAP-Elites): an initial population of random
// genotypes, then generations of `batch_size` offspring, each a mutated copy of a parent drawn
// uniformly from the filled cells; no crossover. Descriptors come from a FeatureMap; the
// archive is a grid (the paper's) or any other EliteArchive.
#include <algorithm>
#include <array>
#include <concepts>
#include <functional>
#include <memory>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/archive/any_archive.hpp"
#include "qdmeta/archive/archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/copy_row.hpp"
#include "qdmeta/core/memory_estimate.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/featuremap/feature_map.hpp"

namespace qdmeta {

struct MapElitesParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp).
  static constexpr IntParam kBatchSize{"map_elites", "batch_size", 1, 10'000'000, "offspring per generation"};
  static constexpr IntParam kInitialPopulation{"map_elites", "initial_population", 1, 100'000'000,
      "random genotypes evaluated in the first generation"};
  Index batch_size = 400;          // offspring per generation, >= 1
  Index initial_population = 2000; // random genotypes evaluated first, >= 1
  void validate() const;
};

// What MAP-Elites allocates besides its archive (grid_archive_bytes): a generation's offspring.
void add_map_elites_memory(MemoryEstimate& m, const MapElitesParams& p, const Task& task);

// Building blocks shared with QD-Meta's per-map evolution and CVT-MAP-Elites.
// Fills `genotypes` (count x n) uniformly at random in [0, 1].
void random_genotypes(RowMatrix& genotypes, Rng& rng);
// Offspring by the caller's operator (Mutation::plugged): per row, in order, its parent and its
// second parent, each pick_parent(rng) (which may record its choice), then the operator's seed
// from `rng`, so the call is as deterministic as the operator is given its seed.
template <class PickParent>
void vary_plugged(PickParent&& pick_parent, const Mutation& mutation, Rng& rng, RowMatrix& offspring) {
  const Index n = offspring.cols();
  RowMatrix parents(offspring.rows(), n), partners(offspring.rows(), n);
  for (Index r = 0; r < offspring.rows(); ++r) {
    copy_row(pick_parent(rng), n, parents.row(r).data());
    copy_row(pick_parent(rng), n, partners.row(r).data());
  }
  mutation.vary(parents, partners, rng(), offspring);
}

// Fills `offspring` (rows already sized) with mutated copies of parents, all drawn first:
// pick_parent(rng) returns a pointer to one parent's genes (any archive's selection). Iso+line
// and a caller's operator draw, row by row, the parent, then the second parent.
template <class PickParent>
void mutate_copies(PickParent&& pick_parent, const Mutation& mutation, Rng& rng, RowMatrix& offspring) {
  const Index n = offspring.cols();
  if (mutation.plugged()) {
    vary_plugged(pick_parent, mutation, rng, offspring);
    return;
  }
  if (mutation.needs_two_parents()) {
    for (Index r = 0; r < offspring.rows(); ++r) {
      Real* child = offspring.row(r).data();
      copy_row(pick_parent(rng), n, child);
      mutation.apply_iso_line(child, pick_parent(rng), n, rng);
    }
    return;
  }
  for (Index r = 0; r < offspring.rows(); ++r) copy_row(pick_parent(rng), n, offspring.row(r).data());
  mutation.apply(offspring, rng);
}

// Iso+line offspring of uniformly drawn elites: for each row in order, its parent cell, its
// second parent cell (independent, so possibly the same), then its variation.
template <EliteArchive Archive>
void generate_iso_line_offspring(const Archive& archive, const Mutation& mutation, Rng& rng, RowMatrix& offspring,
                                 std::vector<Index>* parents) {
  const Index n = offspring.cols();
  for (Index r = 0; r < offspring.rows(); ++r) {
    const Index cell = archive.sample_cell(rng);
    const Index other = archive.sample_cell(rng);
    Real* child = offspring.row(r).data();
    copy_row(archive.solution(cell), n, child);
    mutation.apply_iso_line(child, archive.solution(other), n, rng);
    if (parents) (*parents)[static_cast<std::size_t>(r)] = cell;
  }
}

// Fills `offspring` (rows already sized) with mutated copies of uniformly drawn elites of any
// archive (GridArchive, CvtArchive); with `parents`, records each row's parent cell there.
template <EliteArchive Archive>
void generate_offspring(const Archive& archive, const Mutation& mutation, Rng& rng, RowMatrix& offspring,
                        std::vector<Index>* parents = nullptr) {
  const Index n = offspring.cols();
  const Index rows = offspring.rows();
  if (parents) parents->resize(static_cast<std::size_t>(rows));
  if (mutation.plugged()) {
    Index picks = 0;  // even: a row's parent (recorded), odd: its second parent
    vary_plugged(
        [&](Rng& r) {
          const Index cell = archive.sample_cell(r);
          if (parents && picks % 2 == 0) (*parents)[static_cast<std::size_t>(picks / 2)] = cell;
          ++picks;
          return archive.solution(cell);
        },
        mutation, rng, offspring);
    return;
  }
  if (mutation.needs_two_parents()) {
    generate_iso_line_offspring(archive, mutation, rng, offspring, parents);
    return;
  }
  // In chunks: the chunk's parents drawn (in row order, as before), their rows prefetched, then
  // copied; the elites are random rows of a table larger than L2, so the copies would otherwise
  // wait on one cache miss after another.
  constexpr Index kChunk = 64;
  std::array<Index, kChunk> cells;
  for (Index first = 0; first < rows; first += kChunk) {
    const Index count = std::min(kChunk, rows - first);
    for (Index i = 0; i < count; ++i) {
      cells[static_cast<std::size_t>(i)] = archive.sample_cell(rng);
      const Real* parent = archive.solution(cells[static_cast<std::size_t>(i)]);
      __builtin_prefetch(parent);
      __builtin_prefetch(parent + n - 1);
    }
    for (Index i = 0; i < count; ++i) {
      const Index cell = cells[static_cast<std::size_t>(i)];
      copy_row(archive.solution(cell), n, offspring.row(first + i).data());
      if (parents) (*parents)[static_cast<std::size_t>(first + i)] = cell;
    }
  }
  mutation.apply(offspring, rng);
}

// The candidates of one MAP-Elites generation into `genotypes` (n columns): random genotypes
// while the archive is empty (the initial population in generation 0, a batch after, when every
// solution so far was invalid), else a batch of mutated elites. Each generation has its own
// stream, (seed, kInitialPopulation or kVariation, generation). With `parents`, records each
// row's parent cell there (-1 for random genotypes).
template <EliteArchive Archive>
void next_genotypes(const Archive& archive, const MapElitesParams& params, const Mutation& mutation,
                    std::uint64_t seed, std::int64_t generation, Index n, RowMatrix& genotypes,
                    std::vector<Index>* parents = nullptr) {
  const auto g = static_cast<std::uint64_t>(generation);
  if (archive.empty()) {
    genotypes.resize(generation == 0 ? params.initial_population : params.batch_size, n);
    Rng rng = Rng::stream(seed, {key(StreamKey::kInitialPopulation), g});
    random_genotypes(genotypes, rng);
    if (parents) parents->assign(static_cast<std::size_t>(genotypes.rows()), -1);
  } else {
    genotypes.resize(params.batch_size, n);
    Rng rng = Rng::stream(seed, {key(StreamKey::kVariation), g});
    generate_offspring(archive, mutation, rng, genotypes, parents);
  }
}
// Maps base features to target features and adds the valid rows in batch order
// (archive.add_batch; base features go along when the archive keeps them). `targets` is a
// scratch buffer. Returns the number of rows that entered the archive.
template <EliteArchive Archive>
Index insert_batch(Archive& archive, const FeatureMap& feature_map, const RowMatrix& genotypes,
                   const EvaluationBatch& evaluations, RowMatrix& targets) {
  const Index count = genotypes.rows();
  targets.resize(count, feature_map.output_size());
  feature_map.map(evaluations.base_features.data(), count, targets.data());
  return archive.add_batch({genotypes,
                            {evaluations.fitness.data(), static_cast<std::size_t>(evaluations.fitness.size())},
                            targets,
                            evaluations.base_features,
                            evaluations.valid});
}

// MAP-Elites over any archive that models EliteArchive (archive/archive.hpp): the grid of
// the paper (MapElites), a CVT archive, or a user's own. The archive holds the task's genotypes
// and is usually handed in empty (with elites, the first generation mutates them: a warm
// start); the feature-map turns base features into its descriptors.
template <EliteArchive Archive>
class BasicMapElites final : public Algorithm {
 public:
  BasicMapElites(MapElitesParams params, Task task, std::unique_ptr<FeatureMap> feature_map, Archive archive,
                 MutationParams mutation, std::uint64_t seed);
  // A grid archive from its parameters, completed from the task (solution size, qd_offset).
  BasicMapElites(MapElitesParams params, Task task, std::unique_ptr<FeatureMap> feature_map,
                 GridArchiveParams archive, MutationParams mutation, std::uint64_t seed)
    requires std::same_as<Archive, GridArchive>
      : BasicMapElites(params, task, std::move(feature_map), GridArchive(complete_grid(std::move(archive), task)),
                       mutation, seed) {}

  std::string name() const override { return "map-elites"; }
  std::int64_t generation() const override { return generation_; }
  ArchiveStats stats() const override { return archive_.stats(); }
  EliteTable elites() const override { return archive_.elites(); }
  const Archive& archive() const { return archive_; }
  // From then on, offspring come from `variation` instead of the [mutation] operator (the
  // initial population stays random); not saved by save(): a loaded run needs it again. The
  // same as building with MutationParams::variation.
  void set_variation(VariationFunction variation) {
    MutationParams p = mutation_.params();
    p.variation = std::move(variation);
    p.variation_name = "variation";
    mutation_ = Mutation(std::move(p));
  }
  // Starts from `archive`'s elites instead of the empty archive built (a warm start: the first
  // generation mutates them), before the first step; the caller checks that its shape fits.
  void start_from(Archive archive) {
    if (generation_ != 0 || step_in_progress() || !archive_.empty())
      throw Error("map-elites: an archive can be given only before the first step");
    archive_ = std::move(archive);
  }
  bool checkpointable() const override { return true; }
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

 protected:
  // One request per step: the generation's genotypes, one job.
  void next_request(std::vector<EvaluationJob>& jobs) override;
  bool take_results() override;
  // A step changes the state only in its one tell(): undoing it is dropping its request.
  void save_undo(BinaryWriter& out) const override { save_generation_undo(out); }
  void load_undo(BinaryReader& in) override { load_generation_undo(in); }

 private:
  static GridArchiveParams complete_grid(GridArchiveParams p, const Task& task) {
    p.solution_size = task.genotype_size();
    p.qd_offset = task.qd_offset();
    return p;
  }

  MapElitesParams params_;
  Task task_;
  std::unique_ptr<FeatureMap> feature_map_;
  Archive archive_;
  Mutation mutation_;
  std::uint64_t seed_;
  std::int64_t generation_ = 0;
  RowMatrix genotypes_;
  EvaluationBatch evaluations_;
  RowMatrix targets_;
};

// The paper's MAP-Elites: a grid over the feature-map's target features.
using MapElites = BasicMapElites<GridArchive>;
extern template class BasicMapElites<GridArchive>;
// MAP-Elites over an archive a config chose by kind (plugin/part_registries.hpp).
extern template class BasicMapElites<AnyArchive>;

// Checks that the feature-map and the archive fit `task` (InputError naming what differs).
void check_map_elites_parts(const Task& task, const FeatureMap* feature_map, Index archive_solution_size,
                            Index archive_dimensions);

template <EliteArchive Archive>
BasicMapElites<Archive>::BasicMapElites(MapElitesParams params, Task task, std::unique_ptr<FeatureMap> feature_map,
                                        Archive archive, MutationParams mutation, std::uint64_t seed)
    : params_(params),
      task_(std::move(task)),
      feature_map_(std::move(feature_map)),
      archive_(std::move(archive)),
      mutation_(std::move(mutation)),
      seed_(seed) {
  params_.validate();
  check_map_elites_parts(task_, feature_map_.get(), archive_.solution_size(), archive_.dimensions());
}

template <EliteArchive Archive>
void BasicMapElites<Archive>::next_request(std::vector<EvaluationJob>& jobs) {
  const Index n = task_.genotype_size();
  next_genotypes(archive_, params_, mutation_, seed_, generation_, n, genotypes_);
  evaluations_.resize(genotypes_.rows(), task_.base_feature_size());
  jobs.push_back({&task_, {genotypes_.data(), genotypes_.rows(), n}, evaluations_.view()});
}

template <EliteArchive Archive>
bool BasicMapElites<Archive>::take_results() {
  insert_batch(archive_, *feature_map_, genotypes_, evaluations_, targets_);
  ++generation_;
  return true;
}

template <EliteArchive Archive>
void BasicMapElites<Archive>::save(BinaryWriter& out) const {
  require_between_steps("save()");
  out.tag("map_elites");
  out.value(generation_);
  save_counters(out, counters());
  archive_.save(out);
}

template <EliteArchive Archive>
void BasicMapElites<Archive>::load(BinaryReader& in) {
  require_between_steps("load()");
  in.expect_tag("map_elites");
  generation_ = in.value<std::int64_t>("generation");
  restore_counters(load_counters(in));
  archive_.load(in);
}

}  // namespace qdmeta
