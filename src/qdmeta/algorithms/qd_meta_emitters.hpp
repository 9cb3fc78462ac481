#pragma once
// QD-Meta's bottom level on CMA-MAE emitters (qd_meta.bottom_level = "cma-mae";
// docs/specification.md, "QD-Meta over CMA-MAE"): for one map of one meta-generation, a scheduler
// over the map's rebuilt archive whose thresholds start at the archive's elites and whose emitters
// start from elites drawn from it. Nothing of it outlives the meta-generation: the next one
// rebuilds the archive under another feature-map, and makes a new scheduler.
#include <memory>

#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/emitters/scheduler.hpp"
#include "qdmeta/featuremap/feature_map.hpp"

namespace qdmeta {

// A scheduler over `archive` (which must outlive it): thresholds at the elites' objectives
// (Scheduler::start_thresholds_at_elites), and emitter k's first mean a uniformly drawn elite,
// drawn in emitter order from `rng` (params.emitter.x0 while the archive is empty).
std::unique_ptr<Scheduler<GridArchive>> start_map_emitters(GridArchive& archive, const CmaMaeParams& params, Rng& rng);

// Tells `scheduler` the evaluations of its last ask(), in ask order: `feature_map` turns their
// base features into the archive's measures (`targets` is scratch). An invalid row's fitness and
// base features are first overwritten (lowest fitness, zeros), as algorithm "cma-mae" does, so
// that the emitters' rankings stay finite; such a row enters neither the archive nor the database.
void tell_map_emitters(Scheduler<GridArchive>& scheduler, const FeatureMap& feature_map, EvaluationBatch& evaluations,
                       RowMatrix& targets);

}  // namespace qdmeta
