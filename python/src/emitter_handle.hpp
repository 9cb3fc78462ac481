#pragma once
// A CMA-ME / CMA-MAE emitter as Python holds it (qdmeta.EvolutionStrategyEmitter,
// qdmeta.GaussianEmitter, qdmeta.IsoLineEmitter): the C++ emitter (emitters/), its own random stream (pyribs seeds each
// emitter on its own), the Python archive it draws elites from (kept alive beside it) and the
// constructor's arguments, from which unpickling rebuilds it.
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <utility>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/emitters/emitter.hpp"

namespace qdmeta::python {

struct EmitterHandle {
  pybind11::object archive;       // a qdmeta.GridArchive or CvtArchive
  std::string kind;               // "EvolutionStrategyEmitter", "GaussianEmitter" or "IsoLineEmitter"
  pybind11::tuple parameters;     // build_emitter()'s, as pickled
  std::unique_ptr<Emitter> emitter;
  Rng rng;

  // The emitter's checkpoint and its stream, for bit-exact continuation.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);
};

// One C++ type per Python class (pybind11 binds a type once).
struct EvolutionStrategyEmitterHandle final : EmitterHandle {};
struct GaussianEmitterHandle final : EmitterHandle {};
struct IsoLineEmitterHandle final : EmitterHandle {};

// Makes `h` the emitter `kind` of `parameters` (see emitter_handle.cpp for their order) over
// `archive`; InputError naming the argument when one is invalid.
void build_emitter(EmitterHandle& h, pybind11::object archive, const std::string& kind, pybind11::tuple parameters,
                   Rng rng);

// A qdmeta archive's solution_dim, and its measure extents (a grid's upper - lower bounds; a
// CVT archive's 1 per measure, as its centroids lie in [0, 1]); TypeError for other objects.
Index archive_solution_dim(pybind11::handle archive);
std::vector<double> archive_measure_ranges(pybind11::handle archive);

// What a Scheduler holds: the handle's emitter, asked with the handle's own stream.
class HandleEmitter final : public Emitter {
 public:
  explicit HandleEmitter(std::shared_ptr<EmitterHandle> h) : h_(std::move(h)) {}
  Index batch_size() const override { return h_->emitter->batch_size(); }
  Index solution_size() const override { return h_->emitter->solution_size(); }
  const RowMatrix& ask(Rng& /*scheduler's*/) override { return h_->emitter->ask(h_->rng); }
  void tell(const EmitterResults& results) override { h_->emitter->tell(results); }
  std::int64_t ended_runs() const override { return h_->emitter->ended_runs(); }
  bool tells_alone() const override { return h_->emitter->tells_alone(); }
  // Its own stream, and the library's emitters read nothing but the archive while asked.
  bool asks_alone() const override { return true; }
  void save(BinaryWriter& out) const override { h_->save(out); }
  void load(BinaryReader& in) override { h_->load(in); }

 private:
  std::shared_ptr<EmitterHandle> h_;
};

}  // namespace qdmeta::python
