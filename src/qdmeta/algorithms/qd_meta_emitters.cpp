#include "qdmeta/algorithms/qd_meta_emitters.hpp"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace qdmeta {

std::unique_ptr<Scheduler<GridArchive>> start_map_emitters(GridArchive& archive, const CmaMaeParams& params, Rng& rng) {
  std::vector<std::unique_ptr<Emitter>> emitters;
  const ElitePicker pick = elite_picker(archive);
  const EvolutionStrategyEmitterParams& p = params.emitter;
  for (int k = 0; k < params.emitters; ++k) {
    std::vector<double> x0 = p.x0;
    if (pick(rng, x0) && p.bounds != CmaBoundsHandling::kNone)
      for (double& x : x0) x = std::clamp(x, p.lower_bound, p.upper_bound);  // as a restart's mean
    emitters.push_back(make_configured_emitter(params, std::move(x0), pick));
  }
  auto scheduler = std::make_unique<Scheduler<GridArchive>>(archive, params.thresholds, std::move(emitters), params.add_mode);
  scheduler->start_thresholds_at_elites();
  return scheduler;
}

void tell_map_emitters(Scheduler<GridArchive>& scheduler, const FeatureMap& feature_map, EvaluationBatch& evaluations,
                       RowMatrix& targets) {
  const Index rows = evaluations.size();
  for (Index r = 0; r < rows; ++r) {
    if (evaluations.valid[static_cast<std::size_t>(r)]) continue;
    evaluations.base_features.row(r).setZero();
    evaluations.fitness[r] = std::numeric_limits<Real>::lowest();
  }
  targets.resize(rows, feature_map.output_size());
  feature_map.map(evaluations.base_features.data(), rows, targets.data());
  scheduler.tell({evaluations.fitness.data(), static_cast<std::size_t>(rows)}, targets, evaluations.valid,
                 evaluations.base_features);
}

}  // namespace qdmeta
