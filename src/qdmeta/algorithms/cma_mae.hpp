#pragma once
// CMA-ME and CMA-MAE as a run's algorithm (Fontaine et al. 2020; Fontaine & Nikolaidis 2023):
// each step is one iteration of the emitter scheduler (emitters/scheduler.hpp): every emitter's
// batch is asked, the rows are evaluated as one job, the feature-map turns their base features
// into measures, and the scheduler is told. The archive (a grid or CVT cells) is the result
// archive, each cell keeping its best elite; the per-cell thresholds are the scheduler's. There is
// no initial population: the emitters start from x0. A step's random stream is derived from
// (seed, kVariation, generation), so a checkpoint holds no generator state.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/evaluator.hpp"
#include "qdmeta/core/memory_estimate.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/emitters/scheduler.hpp"
#include "qdmeta/featuremap/feature_map.hpp"

namespace qdmeta {

// Which emitters a run makes ([emitters] kind): CMA-ME's evolution-strategy emitters, or the
// Gaussian and iso+line variation as emitters (MAP-Elites and MAP-Elites (line) under the same
// scheduler and thresholds, as the CMA-MAE paper's baselines run).
enum class EmitterKind { kEvolutionStrategy, kGaussian, kIsoLine };
inline constexpr EnumNames<EmitterKind, 3> kEmitterKindNames{{{EmitterKind::kEvolutionStrategy, "evolution-strategy"},
                                                              {EmitterKind::kGaussian, "gaussian"},
                                                              {EmitterKind::kIsoLine, "iso-line"}}};
std::string to_string(EmitterKind value);

struct CmaMaeParams {
  std::string name = "cma-mae";            // what name() returns: "cma-me" or "cma-mae"
  static constexpr IntParam kCount{"emitters", "count", 1, 10'000,
                                   "emitters; each evolution-strategy emitter has its own CMA-ES (15 in the CMA-MAE paper)"};
  int emitters = 15;                       // emitters (kCount)
  EmitterKind kind = EmitterKind::kEvolutionStrategy;
  // Every gene of the first mean (or parent), as the config gives it: genes live in [0, 1].
  static constexpr RealParam kX0{"emitters", "x0", 0.0, 1.0, Open::kNone,
                                 "every gene of the first mean (pyribs's `x0`, one value for all genes); restarts "
                                 "start from a uniformly drawn elite; the Gaussian and iso+line emitters' parent while "
                                 "the archive is empty"};
  // kEvolutionStrategy: every emitter's. Every kind takes x0 (one value per gene), batch_size
  // and the gene bounds (lower_bound, upper_bound unless bounds = none) from here.
  EvolutionStrategyEmitterParams emitter;
  double sigma = 0.1;        // kGaussian: the noise's SD on every gene (> 0)
  double iso_sigma = 0.01;   // kIsoLine: the isotropic noise's SD (>= 0)
  double line_sigma = 0.2;   // kIsoLine: the SD of the step along x_j - x_i (>= 0)
  ThresholdParams thresholds;  // learning rate alpha and threshold_min
  AddMode add_mode = AddMode::kSingle;  // how a batch meets the thresholds (pyribs's add_mode)
  // Throws InputError naming the field, its value and the rule it breaks.
  void validate() const;
};

// One emitter of p's kind, its first mean or parent x0, drawing elites with `pick`.
std::unique_ptr<Emitter> make_configured_emitter(const CmaMaeParams& p, std::vector<double> x0, ElitePicker pick);

// What CMA-ME allocates besides its archive: the thresholds, each emitter's CMA-ES, the batch.
void add_cma_mae_memory(MemoryEstimate& m, const CmaMaeParams& p, double cells, const Task& task);

// Makes the empty archive when the first step needs it, on the workers of `workers` or on the
// calling thread when it is null (the same archive either way: CVT's centroids take minutes).
template <class A>
using ArchiveSource = std::function<A(Evaluator* workers)>;

template <CellIndexedArchive A>
class CmaMae final : public Algorithm {
 public:
  // `feature_map` turns the task's base features into the archive's measures.
  CmaMae(CmaMaeParams params, Task task, std::unique_ptr<FeatureMap> feature_map, ArchiveSource<A> make_archive,
         std::uint64_t seed);
  // The scheduler and its emitters hold the archive by reference: the algorithm stays put.
  CmaMae(const CmaMae&) = delete;
  CmaMae& operator=(const CmaMae&) = delete;

  std::string name() const override { return params_.name; }
  std::int64_t generation() const override { return generation_; }
  ArchiveStats stats() const override;
  EliteTable elites() const override;
  // The emitters' CMA-ES restarts so far, for summary.json.
  std::vector<std::pair<std::string, double>> summary_extras() const override;

  // Makes the archive and the scheduler (step() calls it; a first ask() without it makes them on
  // the calling thread).
  void prepare(Evaluator& evaluator) { make_parts(&evaluator); }
  bool prepared() const { return archive_.has_value(); }
  const A& archive() const;
  const Scheduler<A>& scheduler() const;
  bool checkpointable() const override { return true; }
  // The archive, then the scheduler's thresholds, emitters and last batch.
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

 protected:
  // One request per step: the scheduler's batch, one job.
  void next_request(std::vector<EvaluationJob>& jobs) override;
  bool take_results() override;
  void before_step(Evaluator& evaluator) override { prepare(evaluator); }
  // The scheduler tells its evolution-strategy emitters at once: on the evaluator's threads.
  bool parallel_inside() const override { return true; }
  // ask() changes the emitters (a restart happens there), tell() the archive too: the undo is
  // the generation and the scheduler; a failed step never reached the archive.
  void save_undo(BinaryWriter& out) const override;
  void load_undo(BinaryReader& in) override;

 private:
  void make_parts(Evaluator* workers);
  void make_scheduler();

  CmaMaeParams params_;
  Task task_;
  std::unique_ptr<FeatureMap> feature_map_;
  ArchiveSource<A> make_archive_;
  std::uint64_t seed_;
  std::optional<A> archive_;  // before scheduler_, which refers to it
  std::optional<Scheduler<A>> scheduler_;
  std::int64_t generation_ = 0;
  EvaluationBatch evaluations_;
  RowMatrix measures_;
};

extern template class CmaMae<GridArchive>;
extern template class CmaMae<CvtArchive>;

}  // namespace qdmeta
