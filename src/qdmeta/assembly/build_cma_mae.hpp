#pragma once
// The builders of algorithms "cma-me" and "cma-mae" (algorithms/cma_mae.hpp): one algorithm, two
// names with the papers' defaults. [emitters] sets the evolution-strategy emitters, [archive]
// the result archive (a grid, or kind "cvt" with [cvt]'s centroids) and, for cma-mae, the
// learning rate and threshold_min, as pyribs's archives take them. docs/config.md lists the keys.
#include <vector>

#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/plugin/algorithm_builder.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {

// CMA-ME: alpha 1, no threshold_min; two-stage improvement, filter, no-improvement restarts.
AlgorithmMaker build_cma_me(AlgorithmBuild& build);
// CMA-MAE: learning_rate (default 0.01) and threshold_min (default the task's QD-score offset);
// improvement ranker, mu selection, basic restarts (the CMA-MAE paper's).
AlgorithmMaker build_cma_mae(AlgorithmBuild& build);

// [emitters] with CMA-MAE's defaults and [archive]'s learning_rate and threshold_min, as
// "cma-mae" reads them, for QD-Meta's qd_meta.bottom_level = "cma-mae". `measure_ranges`: the
// archive's extent along each measure (the random-direction rankers').
CmaMaeParams read_cma_mae_emitters(ConfigReader& emitters, ConfigReader& archive, const Task& task,
                                   std::vector<double> measure_ranges);

}  // namespace qdmeta
