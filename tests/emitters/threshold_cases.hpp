#pragma once
// What the threshold and scheduler tests share (cell_thresholds_test.cpp, batch_thresholds_test.cpp,
// scheduler_test.cpp): CMA-MAE's threshold settings by value, and one outcome checked against its
// hand-worked status and value.
#include <gtest/gtest.h>

#include <limits>

#include "qdmeta/archive/elite_batch.hpp"
#include "qdmeta/emitters/cell_thresholds.hpp"

namespace qdmeta::test {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

inline ThresholdParams mae(double alpha, double threshold_min) {
  ThresholdParams p;
  p.alpha = alpha;
  p.threshold_min = threshold_min;
  return p;
}

inline void expect_outcome(const ThresholdOutcome& o, AddStatus status, double improvement) {
  EXPECT_EQ(o.status, status);
  EXPECT_EQ(o.improvement, improvement);
}

}  // namespace qdmeta::test
