#pragma once
// Shared test assertion: two elite tables hold the same elites, bit for bit (same cells, floats
// compared exactly), as determinism tests need.
#include <gtest/gtest.h>

#include "qdmeta/archive/elite_table.hpp"

namespace qdmeta {

inline void expect_same_elites(const EliteTable& a, const EliteTable& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.objective, b.objective);
  EXPECT_TRUE(a.solutions == b.solutions);
  EXPECT_TRUE(a.measures == b.measures);
  EXPECT_TRUE(a.base_features == b.base_features);
}

}  // namespace qdmeta
