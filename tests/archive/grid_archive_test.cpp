// Tests of src/qdmeta/archive/grid_archive.{hpp,cpp}: pyribs-style binning at the edges,
// row-major cell numbering, strictly-better replacement, statistics, and parameter checks.
#include "qdmeta/archive/grid_archive.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

GridArchiveParams params(std::vector<int> bins, Index solution_size = 2, double lower = 0.0, double upper = 1.0) {
  GridArchiveParams p;
  p.bins = std::move(bins);
  p.solution_size = solution_size;
  p.lower = lower;
  p.upper = upper;
  return p;
}

Index bin1(const GridArchive& a, Real m) { return a.index_of(&m); }

std::string message_of(const GridArchiveParams& p) {
  try {
    p.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no exception)";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(GridArchive, ValuesGoToTheCorrectBin) {
  // After pyribs's test_values_go_to_correct_bin: 100 bins over [0, 1].
  const GridArchive a(params({100}));
  EXPECT_EQ(bin1(a, 0.0f), 0);     // lower bound -> first bin
  EXPECT_EQ(bin1(a, 1.0f), 99);    // upper bound -> last bin
  EXPECT_EQ(bin1(a, -0.5f), 0);    // below the range -> first bin
  EXPECT_EQ(bin1(a, -1e30f), 0);
  EXPECT_EQ(bin1(a, 2.0f), 99);    // above the range -> last bin
  EXPECT_EQ(bin1(a, 1e30f), 99);
  EXPECT_EQ(bin1(a, std::numeric_limits<Real>::infinity()), 99);
  EXPECT_EQ(bin1(a, -std::numeric_limits<Real>::infinity()), 0);
  // Exactly on an inner edge -> the upper bin, although 0.01f * 100 = 0.99999997 (epsilon rule).
  EXPECT_EQ(bin1(a, 0.01f), 1);
  EXPECT_EQ(bin1(a, 0.5f), 50);
  EXPECT_EQ(bin1(a, 0.99f), 99);
  EXPECT_EQ(bin1(a, 0.07f), 7);
  // Just below an edge (by more than epsilon / bins) -> the lower bin.
  EXPECT_EQ(bin1(a, 0.00999f), 0);
  EXPECT_EQ(bin1(a, 0.4999f), 49);
  EXPECT_EQ(bin1(a, 0.98999f), 98);
  // Within epsilon / bins = 1e-8 below an edge still counts as on the edge.
  EXPECT_EQ(bin1(a, std::nextafter(0.01f, 0.0f)), 1);
  // Inside a bin.
  EXPECT_EQ(bin1(a, 0.015f), 1);
  EXPECT_EQ(bin1(a, 0.995f), 99);
}

TEST(GridArchive, EveryInnerEdgeGoesUp) {
  for (int bins : {10, 100, 7}) {
    const GridArchive a(params({bins}));
    for (int k = 1; k < bins; ++k) {
      const auto edge = static_cast<Real>(static_cast<double>(k) / bins);
      EXPECT_EQ(bin1(a, edge), k) << "edge " << k << "/" << bins;
      EXPECT_EQ(bin1(a, edge - 1e-4f / static_cast<Real>(bins)), k - 1) << "below edge " << k << "/" << bins;
    }
  }
}

TEST(GridArchive, NonUnitRange) {
  const GridArchive a(params({10}, 1, -1.0, 1.0));
  EXPECT_EQ(bin1(a, -1.0f), 0);
  EXPECT_EQ(bin1(a, -0.8f), 1);  // edge
  EXPECT_EQ(bin1(a, -0.81f), 0);
  EXPECT_EQ(bin1(a, 0.0f), 5);
  EXPECT_EQ(bin1(a, -0.01f), 4);
  EXPECT_EQ(bin1(a, 1.0f), 9);
  EXPECT_EQ(bin1(a, 0.95f), 9);
  EXPECT_EQ(bin1(a, -3.0f), 0);
}

// pyribs's `ranges`: each measure binned over its own [lower_bounds[d], upper_bounds[d]], the
// scalar lower/upper unused; the cell index computed by hand for each measure.
TEST(GridArchive, PerMeasureRangesBinEachMeasureOverItsOwnRange) {
  GridArchiveParams p = params({4, 10}, 1, 7.0, 9.0);  // scalar bounds that must not be used
  p.lower_bounds = {-2.0, 0.0};
  p.upper_bounds = {2.0, 100.0};
  const GridArchive a(p);
  const auto cell = [&](Real m0, Real m1) {
    const Real m[2] = {m0, m1};
    return a.index_of(m);
  };
  EXPECT_EQ(cell(-1.5f, 95.0f), 0 * 10 + 9);  // floor(0.5 / 4 * 4) = 0, floor(95 / 100 * 10) = 9
  EXPECT_EQ(cell(1.5f, 5.0f), 3 * 10 + 0);
  EXPECT_EQ(cell(0.0f, 50.0f), 2 * 10 + 5);   // on inner edges: the upper bin, as pyribs
  EXPECT_EQ(cell(3.0f, -7.0f), 3 * 10 + 0);   // outside: the edge bins
  EXPECT_EQ(p.lower_of(1), 0.0);
  EXPECT_EQ(p.upper_of(0), 2.0);
}

TEST(GridArchive, PerMeasureRangesAreChecked) {
  GridArchiveParams p = params({4, 10});
  p.lower_bounds = {-2.0};
  p.upper_bounds = {2.0};
  EXPECT_EQ(message_of(p), "archive ranges: 1 lower and 1 upper bounds for 2 target features: give one "
                          "(lower, upper) pair per feature");
  p.lower_bounds = {-2.0, 5.0};
  p.upper_bounds = {2.0, 5.0};
  EXPECT_TRUE(contains(message_of(p), "lower must be below upper")) << message_of(p);
  p.upper_bounds = {2.0};
  EXPECT_TRUE(contains(message_of(p), "archive ranges: 2 lower and 1 upper bounds")) << message_of(p);
  p.upper_bounds = {2.0, 6.0};
  EXPECT_EQ(message_of(p), "(no exception)");
}

TEST(GridArchive, RowMajorCellIndex) {
  const GridArchive a(params({2, 3, 4}));
  EXPECT_EQ(a.cells(), 24);
  EXPECT_EQ(a.dimensions(), 3);
  std::set<Index> seen;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k) {
        const Real m[3] = {(i + 0.5f) / 2, (j + 0.5f) / 3, (k + 0.5f) / 4};
        const Index cell = a.index_of(m);
        EXPECT_EQ(cell, i * 12 + j * 4 + k) << i << "," << j << "," << k;  // C order: last varies fastest
        seen.insert(cell);
      }
  EXPECT_EQ(seen.size(), 24u);
  const Real corner[3] = {1.0f, 1.0f, 1.0f};
  EXPECT_EQ(a.index_of(corner), 23);
  const Real mixed[3] = {1.0f, 0.0f, 0.5f};  // (1, 0, 2)
  EXPECT_EQ(a.index_of(mixed), 14);
}

TEST(GridArchive, AddStatusAndStrictlyBetterReplacement) {
  GridArchive a(params({10, 10}));
  const Real m[2] = {0.15f, 0.25f};
  const Real m_same_cell[2] = {0.19f, 0.21f};
  const Real s1[2] = {0.1f, 0.2f};
  const Real s2[2] = {0.3f, 0.4f};
  const Real s3[2] = {0.5f, 0.6f};
  const Index cell = a.index_of(m);
  EXPECT_EQ(cell, 12);
  EXPECT_FALSE(a.occupied(cell));

  EXPECT_EQ(a.add(s1, 1.0f, m), AddStatus::kNew);
  EXPECT_TRUE(a.occupied(cell));
  EXPECT_EQ(a.size(), 1);
  EXPECT_EQ(a.objective(cell), 1.0f);

  // Equal objective keeps the old elite.
  EXPECT_EQ(a.add(s2, 1.0f, m_same_cell), AddStatus::kNotAdded);
  EXPECT_EQ(a.solution(cell)[0], 0.1f);
  EXPECT_EQ(a.measures(cell)[0], 0.15f);
  // Worse objective too.
  EXPECT_EQ(a.add(s2, 0.5f, m_same_cell), AddStatus::kNotAdded);
  EXPECT_EQ(a.solution(cell)[1], 0.2f);
  EXPECT_EQ(a.objective(cell), 1.0f);
  // Strictly better replaces solution, objective and measures.
  EXPECT_EQ(a.add(s3, std::nextafter(1.0f, 2.0f), m_same_cell), AddStatus::kImproved);
  EXPECT_EQ(a.objective(cell), std::nextafter(1.0f, 2.0f));
  EXPECT_EQ(a.solution(cell)[0], 0.5f);
  EXPECT_EQ(a.solution(cell)[1], 0.6f);
  EXPECT_EQ(a.measures(cell)[0], 0.19f);
  EXPECT_EQ(a.measures(cell)[1], 0.21f);
  EXPECT_EQ(a.size(), 1);
  EXPECT_EQ(a.filled_cells(), std::vector<Index>{12});

  // Negative objectives work for a new cell (no hidden 0 baseline).
  const Real other[2] = {0.95f, 0.95f};
  EXPECT_EQ(a.add(s1, -100.0f, other), AddStatus::kNew);
  EXPECT_EQ(a.objective(99), -100.0f);
  EXPECT_EQ(a.filled_cells(), (std::vector<Index>{12, 99}));

  EXPECT_EQ(static_cast<int>(AddStatus::kNotAdded), 0);
  EXPECT_EQ(static_cast<int>(AddStatus::kImproved), 1);
  EXPECT_EQ(static_cast<int>(AddStatus::kNew), 2);
}

TEST(GridArchive, KeepsBaseFeatures) {
  GridArchiveParams p = params({4});
  p.base_feature_size = 3;
  GridArchive a(p);
  const Real s[2] = {0.0f, 1.0f};
  const Real b1[3] = {0.1f, 0.2f, 0.3f};
  const Real b2[3] = {0.7f, 0.8f, 0.9f};
  const Real m = 0.6f;
  a.add(s, 1.0f, {&m, 1}, b1);
  EXPECT_EQ(a.base_features(2)[2], 0.3f);
  a.add(s, 0.0f, {&m, 1}, b2);  // not added: base features unchanged
  EXPECT_EQ(a.base_features(2)[0], 0.1f);
  a.add(s, 2.0f, {&m, 1}, b2);
  EXPECT_EQ(a.base_features(2)[0], 0.7f);
  EXPECT_EQ(a.base_features(2)[2], 0.9f);
}

TEST(GridArchive, NeverLosesItsBest) {
  GridArchive a(params({10, 10}, 3));
  Rng rng(31);
  std::vector<double> best_in_cell(static_cast<std::size_t>(a.cells()), -std::numeric_limits<double>::infinity());
  double running_max = -std::numeric_limits<double>::infinity();
  for (int t = 0; t < 5000; ++t) {
    const Real m[2] = {static_cast<Real>(rng.uniform(-0.1, 1.1)), static_cast<Real>(rng.uniform(-0.1, 1.1))};
    const Real s[3] = {static_cast<Real>(t), 0.0f, 1.0f};
    const auto f = static_cast<Real>(rng.normal() * 10.0);
    const Index cell = a.index_of(m);
    const bool was_occupied = a.occupied(cell);
    const AddStatus status = a.add(s, f, m);
    running_max = std::max(running_max, static_cast<double>(f));
    ASSERT_EQ(a.stats().obj_max, running_max) << "after insertion " << t;
    // The status agrees with the cell's history, and a cell's objective never decreases.
    const double previous = best_in_cell[static_cast<std::size_t>(cell)];
    const AddStatus expected_status =
        !was_occupied ? AddStatus::kNew : (f > previous ? AddStatus::kImproved : AddStatus::kNotAdded);
    ASSERT_EQ(status, expected_status) << "insertion " << t;
    best_in_cell[static_cast<std::size_t>(cell)] = std::max(previous, static_cast<double>(f));
    for (Index c = 0; c < a.cells(); ++c) {
      const double expect = best_in_cell[static_cast<std::size_t>(c)];
      ASSERT_EQ(a.occupied(c), std::isfinite(expect)) << "cell " << c;
      if (a.occupied(c)) {
        ASSERT_EQ(static_cast<double>(a.objective(c)), expect) << "cell " << c;
      }
    }
  }
  EXPECT_EQ(a.size(), 100);  // 5000 uniform draws fill every cell
}

TEST(GridArchive, StatsAgreeWithARecomputation) {
  GridArchiveParams p = params({20, 5}, 2);
  p.qd_offset = -50.0;
  GridArchive a(p);
  EXPECT_EQ(a.stats(), ArchiveStats{});  // empty: all zero
  Rng rng(32);
  std::map<Index, Real> elites;
  for (int t = 0; t < 200; ++t) {
    const Real m[2] = {static_cast<Real>(rng.uniform()), static_cast<Real>(rng.uniform())};
    const Real s[2] = {0.5f, 0.5f};
    const auto f = static_cast<Real>(rng.uniform(-40.0, 10.0));
    a.add(s, f, m);
    const Index cell = a.index_of(m);
    auto it = elites.find(cell);
    if (it == elites.end()) elites[cell] = f;
    else it->second = std::max(it->second, f);
  }
  double sum = 0.0, best = -1e300;
  for (const auto& [cell, f] : elites) {
    sum += f;
    best = std::max(best, static_cast<double>(f));
  }
  const auto n = static_cast<double>(elites.size());
  const ArchiveStats s = a.stats();
  ASSERT_GT(elites.size(), 50u);
  ASSERT_LT(elites.size(), 100u);  // not full: coverage is a real fraction
  EXPECT_EQ(s.num_elites, static_cast<Index>(elites.size()));
  EXPECT_EQ(a.size(), s.num_elites);
  EXPECT_DOUBLE_EQ(s.coverage, n / 100.0);
  double qd = 0.0;
  for (const auto& [cell, f] : elites) qd += static_cast<double>(f) - (-50.0);
  EXPECT_NEAR(s.qd_score, qd, 1e-9 * std::abs(qd));
  EXPECT_GT(s.qd_score, 0.0);
  EXPECT_NEAR(s.norm_qd_score, qd / 100.0, 1e-9 * std::abs(qd));
  EXPECT_EQ(s.obj_max, best);
  EXPECT_NEAR(s.obj_mean, sum / n, 1e-9 * (std::abs(sum / n) + 1.0));
}

TEST(GridArchive, NanMeasuresThrow) {
  GridArchive a(params({10, 10}));
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real m[2] = {0.5f, nan};
  const Real s[2] = {0.0f, 0.0f};
  EXPECT_THROW(a.index_of(m), Error);
  try {
    a.add(s, 1.0f, m);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "grid archive: row 0 of the batch has measure 1 = nan; measures must be finite");
  }
  EXPECT_TRUE(a.empty());
}

TEST(GridArchive, ParamsValidateMessages) {
  EXPECT_EQ(message_of(params({})), "archive.bins is empty: give the number of bins of each target feature");
  const std::string zero = message_of(params({10, 0}));
  EXPECT_TRUE(contains(zero, "archive.bins = [10, 0]")) << zero;
  EXPECT_TRUE(contains(zero, "at least 1")) << zero;
  EXPECT_TRUE(contains(message_of(params({-3})), "archive.bins = [-3]"));
  const std::string equal = message_of(params({10}, 2, 1.0, 1.0));
  EXPECT_TRUE(contains(equal, "[1, 1]")) << equal;
  EXPECT_TRUE(contains(equal, "lower must be below upper")) << equal;
  EXPECT_TRUE(contains(message_of(params({10}, 2, 2.0, 1.0)), "[2, 1]"));
  EXPECT_TRUE(contains(message_of(params({10}, 2, 0.0, std::numeric_limits<double>::infinity())), "lower must be below upper"));
  EXPECT_TRUE(contains(message_of(params({10}, 0)), "solution size"));
  EXPECT_TRUE(contains(message_of(params({100000, 100000})), "cells"));
  GridArchiveParams negative_base = params({10});
  negative_base.base_feature_size = -1;
  EXPECT_TRUE(contains(message_of(negative_base), "base-feature size"));
  EXPECT_EQ(message_of(params({100, 100}, 20)), "(no exception)");
  EXPECT_THROW(GridArchive{params({10, 0})}, InputError);
}

// A range whose width underflows (1 / width overflows) used to give index_of = INT64_MIN for
// a measure at lower (0 * inf); one whose width overflows put everything in cell 0.
TEST(GridArchive, RangesTooNarrowOrTooWideAreRefused) {
  const std::string narrow = message_of(params({10}, 2, 0.0, 1e-320));
  EXPECT_TRUE(contains(narrow, "archive range [0, 1e-320] is too narrow")) << narrow;
  EXPECT_TRUE(contains(narrow, "smallest normal double")) << narrow;
  EXPECT_TRUE(contains(message_of(params({10}, 2, 1.0, std::nextafter(1.0, 2.0))), "(no exception)"));
  EXPECT_TRUE(contains(message_of(params({10}, 2, 0.0, 3e-308)), "(no exception)"));
  const double big = std::numeric_limits<double>::max();
  const std::string wide = message_of(params({10}, 2, -big, big));
  EXPECT_TRUE(contains(wide, "is too wide: upper - lower overflows")) << wide;
  EXPECT_THROW(GridArchive{params({10}, 2, 0.0, 1e-320)}, InputError);
  // The narrowest range allowed still bins: the lower edge in cell 0, the upper in the last.
  const GridArchive a(params({10}, 2, 0.0, 3e-308));
  const Real lo[1] = {0.0f}, hi[1] = {1.0f};
  EXPECT_EQ(a.index_of(lo), 0);
  EXPECT_EQ(a.index_of(hi), 9);
}

TEST(GridArchive, SampleCellOnlyReturnsFilledCells) {
  GridArchive a(params({10, 10}));
  const Real s[2] = {0.0f, 0.0f};
  for (Real x : {0.05f, 0.35f, 0.75f}) {
    const Real m[2] = {x, 0.55f};
    a.add(s, 1.0f, m);
  }
  const std::set<Index> filled(a.filled_cells().begin(), a.filled_cells().end());
  EXPECT_EQ(filled, (std::set<Index>{5, 35, 75}));
  Rng rng(33);
  std::map<Index, int> counts;
  for (int i = 0; i < 3000; ++i) {
    const Index c = a.sample_cell(rng);
    ASSERT_TRUE(filled.contains(c)) << c;
    ASSERT_TRUE(a.occupied(c));
    ++counts[c];
  }
  for (const auto& [c, n] : counts) EXPECT_NEAR(n, 1000, 6 * std::sqrt(3000 * (1.0 / 3) * (2.0 / 3)));
  EXPECT_EQ(counts.size(), 3u);
}

TEST(GridArchive, ClearForgetsEveryElite) {
  GridArchive a(params({10, 10}));
  const Real s[2] = {0.0f, 0.0f};
  const Real m[2] = {0.5f, 0.5f};
  const Real m2[2] = {0.1f, 0.9f};
  a.add(s, 10.0f, m);
  a.add(s, 20.0f, m2);
  ASSERT_EQ(a.size(), 2);
  a.clear();
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.size(), 0);
  EXPECT_TRUE(a.filled_cells().empty());
  for (Index c = 0; c < a.cells(); ++c) ASSERT_FALSE(a.occupied(c));
  EXPECT_EQ(a.stats(), ArchiveStats{});
  // A worse elite than the cleared one is new again.
  EXPECT_EQ(a.add(s, -1.0f, m), AddStatus::kNew);
  EXPECT_EQ(a.objective(a.index_of(m)), -1.0f);
  EXPECT_EQ(a.size(), 1);
  EXPECT_EQ(a.stats().obj_max, -1.0);
}

}  // namespace
}  // namespace qdmeta
