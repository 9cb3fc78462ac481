#pragma once
// The RHex hexapod as a Task (docs/specification.md, RHex): 24 genes -> Buehler-clock gait -> one DART
// episode -> fitness (forward distance, m), base features (50-D trajectory or 15-D
// feature-sets), valid = 0 when the robot turned over or never settled. DART-free header.
#include <string>

#include "qdmeta/core/params.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/task_shape.hpp"
#include "qdmeta/tasks/rhex/rhex_episode.hpp"

namespace qdmeta {

enum class RhexFeatures { kTrajectory, kFeatureSets };
inline constexpr EnumNames<RhexFeatures, 2> kRhexFeaturesNames{
    {{RhexFeatures::kTrajectory, "trajectory"}, {RhexFeatures::kFeatureSets, "feature-sets"}}};

struct RhexParams {
  // The config parameter read into this struct and checked by validate() (core/params.hpp).
  static constexpr RealParam kGeneStep{"task", "gene_step", 0.0, 1.0, Open::kLower,
      "genes are snapped to this grid before decoding"};
  RhexFeatures features = RhexFeatures::kTrajectory;  // which base features the task writes
  double gene_step = 0.025;                           // genes are snapped to this grid, in (0, 1]
  rhex::StanceOffset stance_offset = rhex::StanceOffset::kPaper;  // the paper's range, or the authors' 6x
  rhex::EpisodeSettings episode;                      // simulation settings
  rhex::RhexEnvironment environment;                  // where `evaluate` runs (default: flat, intact)
  void validate() const;
};

class RhexTask {
 public:
  explicit RhexTask(RhexParams params = {});
  // What the accessors below return, without a task (a resolved config's, core/task_shape.hpp).
  static TaskShape shape_of(const RhexParams& p);
  std::string name() const { return "rhex"; }
  Index genotype_size() const { return rhex::kGenes; }
  Index base_feature_size() const;
  // Each episode builds its own DART world, but DART keeps per-world caches: one copy per worker.
  bool shareable() const { return false; }
  double qd_offset() const { return -1.0; }  // distances below -1 m count 0 in the QD-score
  void evaluate(GenotypeView genotypes, EvaluationView out) const;

  // One episode of one genotype (24 genes in [0, 1]) in `environment`.
  rhex::EpisodeResult episode(const Real* genes, const rhex::RhexEnvironment& environment) const;
  // The gait of a genotype after snapping it to the gene grid.
  rhex::GaitParams gait(const Real* genes) const;
  // Writes the task's base features of an episode (base_feature_size() values).
  void base_features(const rhex::EpisodeResult& result, Real* out) const;
  const RhexParams& params() const { return params_; }

 private:
  RhexParams params_;
};

}  // namespace qdmeta
