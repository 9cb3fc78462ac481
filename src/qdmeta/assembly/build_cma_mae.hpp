#pragma once
// The builders of algorithms "cma-me" and "cma-mae" (algorithms/cma_mae.hpp): one algorithm, two
// names with the papers' defaults. [emitters] sets the evolution-strategy emitters, [archive]
// the result archive (a grid, or kind "cvt" with [cvt]'s centroids) and, for cma-mae, the
// learning rate and threshold_min, as pyribs's archives take them. docs/config.md lists the keys.
#include "qdmeta/plugin/algorithm_builder.hpp"

namespace qdmeta {

// CMA-ME: alpha 1, no threshold_min; two-stage improvement, filter, no-improvement restarts.
AlgorithmMaker build_cma_me(AlgorithmBuild& build);
// CMA-MAE: learning_rate (default 0.01) and threshold_min (default the task's QD-score offset);
// improvement ranker, mu selection, basic restarts (the CMA-MAE paper's).
AlgorithmMaker build_cma_mae(AlgorithmBuild& build);

}  // namespace qdmeta
