#pragma once
// CMA-MAE settings for the algorithm tests: `emitters` emitters of `batch` rows from x0, their
// genes kept in [0, 1] by `bounds`, learning rate `alpha` above threshold_min.
#include <utility>

#include "qdmeta/algorithms/cma_mae.hpp"

namespace qdmeta::test {

inline CmaMaeParams small_cma_mae(int genes, double x0, int emitters, int batch, CmaBoundsHandling bounds,
                                  ThresholdParams thresholds) {
  CmaMaeParams p;
  p.emitters = emitters;
  p.emitter.x0.assign(static_cast<std::size_t>(genes), x0);
  p.emitter.batch_size = batch;
  p.emitter.bounds = bounds;
  p.emitter.lower_bound = 0.0;
  p.emitter.upper_bound = 1.0;
  p.thresholds = thresholds;
  return p;
}

}  // namespace qdmeta::test
