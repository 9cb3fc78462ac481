#pragma once
// An emitter of CMA-ME / CMA-MAE (Fontaine et al. 2020; Fontaine & Nikolaidis 2023): asked, it
// proposes a batch of solutions; told, it learns from how the archive took them. The scheduler
// (scheduler.hpp) asks each emitter in turn, adds every row to the archive under the thresholds
// (thresholded_add.hpp) and tells each emitter the outcomes of its own rows.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/archive/elite_batch.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/params.hpp"
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

// emitters.batch_size, every kind's (docs/config.md): each emitter struct's validate() checks it,
// and the Python emitters take the same range.
inline constexpr IntParam kEmitterBatchSize{"emitters", "batch_size", 1, 1'000'000,
                                            "rows per emitter per step, CMA-ES's lambda (36 in the CMA-MAE paper), "
                                            "every kind"};

// Writes a uniformly drawn elite's genes into `genes` (solution_size values) and returns true,
// or returns false when the archive is empty (scheduler.hpp's elite_picker).
using ElitePicker = std::function<bool(Rng& rng, std::vector<double>& genes)>;

// The checks the variation emitters share (Gaussian, iso+line): x0 non-empty and finite, and
// upper > lower; InputError naming `params` ("GaussianEmitterParams") and the field.
void check_x0_and_bounds(std::string_view params, const std::vector<double>& x0, double lower_bound,
                         double upper_bound);

class Emitter {
 public:
  virtual ~Emitter() = default;
  virtual Index batch_size() const = 0;
  virtual Index solution_size() const = 0;
  // A batch of batch_size() rows of solution_size() genes; valid until the next ask() or load().
  virtual const RowMatrix& ask(Rng& rng) = 0;
  // The outcomes of the last ask()'s rows; InputError when no ask() is pending or the sizes differ.
  virtual void tell(const EmitterResults& results) = 0;
  // How many of its runs have ended (restarts done or due after the last tell), which a
  // BanditScheduler of reselect "terminated" follows; -1 for an emitter without runs (a
  // BanditScheduler then reselects it at every ask, as pyribs's does).
  virtual std::int64_t ended_runs() const { return -1; }
  // True when tell() reads and writes nothing but this emitter and `results` (no shared state,
  // no Python), so a Scheduler may tell several such emitters at once; the default, false, has
  // a user's emitter told on the calling thread in emitter order.
  virtual bool tells_alone() const { return false; }
  // True when ask() ignores the scheduler's stream (the emitter draws from one of its own, as
  // the Python module's emitters do) and only reads what others share (the archive), so a
  // Scheduler may ask several such emitters at once; false by default.
  virtual bool asks_alone() const { return false; }
  // Checkpoints for bit-exact continuation: load() into an emitter built with the same params.
  virtual void save(BinaryWriter& out) const = 0;
  virtual void load(BinaryReader& in) = 0;
};

// What every emitter here shares: its batch, the ask/tell protocol and the batch's checkpoint.
class BatchEmitter : public Emitter {
 public:
  Index batch_size() const override { return batch_.rows(); }
  Index solution_size() const override { return batch_.cols(); }

 protected:
  // `name` starts the protocol's messages ("GaussianEmitter::ask: ...").
  BatchEmitter(Index rows, Index genes, std::string_view name) : batch_(rows, genes), name_(name) {}
  // Throws InputError while a batch awaits its tell (ask() sets awaiting_tell_ once it has its batch).
  void check_ask() const;
  // Throws InputError unless a batch is pending and `results` has its rows, objectives and outcomes.
  void check_tell(const EmitterResults& results) const;
  void save_batch(BinaryWriter& out) const;
  void load_batch(BinaryReader& in);

  RowMatrix batch_;
  bool awaiting_tell_ = false;

 private:
  std::string name_;
};

// An emitter that learns nothing from tell() (Gaussian, iso+line): its checkpoint is its batch,
// under `tag`.
class StatelessEmitter : public BatchEmitter {
 public:
  void tell(const EmitterResults& results) override;
  bool tells_alone() const override { return true; }
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

 protected:
  StatelessEmitter(Index rows, Index genes, std::string_view name, std::string_view tag)
      : BatchEmitter(rows, genes, name), tag_(tag) {}

 private:
  std::string tag_;
};

}  // namespace qdmeta
