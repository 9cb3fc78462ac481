#pragma once
// An emitter of CMA-ME / CMA-MAE (Fontaine et al. 2020; Fontaine & Nikolaidis 2023): asked, it
// proposes a batch of solutions; told, it learns from how the archive took them. The scheduler
// (scheduler.hpp) asks each emitter in turn, adds every row to the archive under the thresholds
// (thresholded_add.hpp) and tells each emitter the outcomes of its own rows.
#include <cstdint>
#include <span>

#include "qdmeta/archive/elite_batch.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"
#include "qdmeta/emitters/cell_thresholds.hpp"

namespace qdmeta {

// What became of the rows of one ask(), in ask() order.
struct EmitterResults {
  RowsView solutions;                            // the rows ask() returned
  std::span<const Real> objectives;              // one per row
  RowsView measures;                             // one row of measures per row
  std::span<const ThresholdOutcome> outcomes;    // status and improvement value per row
  Index rows() const { return solutions.rows; }
};

class Emitter {
 public:
  virtual ~Emitter() = default;
  virtual Index batch_size() const = 0;
  virtual Index solution_size() const = 0;
  // A batch of batch_size() rows of solution_size() genes; valid until the next ask() or load().
  virtual const RowMatrix& ask(Rng& rng) = 0;
  // The outcomes of the last ask()'s rows; InputError when no ask() is pending or the sizes differ.
  virtual void tell(const EmitterResults& results) = 0;
  // Checkpoints for bit-exact continuation: load() into an emitter built with the same params.
  virtual void save(BinaryWriter& out) const = 0;
  virtual void load(BinaryReader& in) = 0;
};

}  // namespace qdmeta
