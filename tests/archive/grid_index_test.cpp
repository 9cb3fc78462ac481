#include "qdmeta/archive/grid_index.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

GridArchiveParams params_of(std::vector<int> bins, double lower, double upper, double epsilon = 1e-6) {
  GridArchiveParams p;
  p.bins = std::move(bins);
  p.lower = lower;
  p.upper = upper;
  p.solution_size = 1;
  p.epsilon = epsilon;
  return p;
}

// The cell formula as GridArchive::index_of first wrote it, one expression per dimension (this
// translation unit is built with the same flags, so the compiler treats it the same way).
Index written_formula(const GridArchiveParams& p, const Real* m) {
  const double scale = 1.0 / (p.upper - p.lower);
  Index cell = 0, stride = 1;
  for (std::size_t d = p.bins.size(); d-- > 0;) {
    const double margin = p.epsilon + p.bins[d] * static_cast<double>(std::numeric_limits<float>::epsilon());
    const double pos = std::floor((static_cast<double>(m[d]) - p.lower) * scale * p.bins[d] + margin);
    cell += static_cast<Index>(std::clamp(pos, 0.0, static_cast<double>(p.bins[d] - 1))) * stride;
    stride *= p.bins[d];
  }
  return cell;
}

// Values every dimension is tried at: the bounds, each bin edge and its float neighbours,
// outside the range, signed zero, huge values, and random ones.
std::vector<Real> edge_values(const GridArchiveParams& p, int bins, std::uint64_t seed) {
  std::vector<Real> v;
  const auto lo = static_cast<float>(p.lower), hi = static_cast<float>(p.upper);
  for (int k = 0; k <= bins; ++k) {
    const auto edge = static_cast<float>(p.lower + (p.upper - p.lower) * k / bins);
    v.insert(v.end(), {edge, std::nextafter(edge, -INFINITY), std::nextafter(edge, INFINITY)});
  }
  v.insert(v.end(), {lo, hi, -0.0f, 0.0f, 1.0f, lo - 1.0f, hi + 1.0f, -1e30f, 1e30f, -INFINITY, INFINITY});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(lo - 0.1f, hi + 0.1f);
  for (int i = 0; i < 500; ++i) v.push_back(u(rng));
  return v;
}

TEST(GridIndex, BlockEqualsScalarEqualsTheWrittenFormula) {
  const std::vector<GridArchiveParams> cases = {
      params_of({100, 100}, 0.0, 1.0), params_of({7}, 0.0, 1.0),         params_of({3, 5, 4}, -2.0, 3.0),
      params_of({1}, 0.0, 1.0),        params_of({1000}, 0.0, 1.0, 0.0), params_of({50, 2}, -1.0, 1.0, 0.25)};
  for (const GridArchiveParams& p : cases) {
    const GridIndex index(p);
    const GridArchive archive(p);
    const auto dims = static_cast<Index>(p.bins.size());
    // Rows: dimension d walks dimension d's edge values while the others take random values.
    std::vector<std::vector<Real>> values;
    Index count = 0;
    for (Index d = 0; d < dims; ++d) {
      values.push_back(edge_values(p, p.bins[static_cast<std::size_t>(d)], static_cast<std::uint64_t>(d + 1)));
      count = std::max(count, static_cast<Index>(values.back().size()));
    }
    const Index ld = count + 3;  // a leading dimension that is not the count
    std::vector<Real> measures_t(static_cast<std::size_t>(dims * ld), 0.5f);
    for (Index d = 0; d < dims; ++d)
      for (Index r = 0; r < count; ++r) {
        const auto& vd = values[static_cast<std::size_t>(d)];
        measures_t[static_cast<std::size_t>(d * ld + r)] = vd[static_cast<std::size_t>((r * (d + 1)) % static_cast<Index>(vd.size()))];
      }
    for (Index n : {count, count - 1, Index{33}, Index{17}, Index{16}, Index{15}, Index{8}, Index{7}, Index{1}, Index{0}}) {
      std::vector<std::int32_t> cells(static_cast<std::size_t>(n) + 1, -7);
      index.cells_of_t(measures_t.data(), ld, n, cells.data());
      EXPECT_EQ(cells[static_cast<std::size_t>(n)], -7) << "wrote past count";
      std::vector<Real> row(static_cast<std::size_t>(dims));
      for (Index r = 0; r < n; ++r) {
        for (Index d = 0; d < dims; ++d) row[static_cast<std::size_t>(d)] = measures_t[static_cast<std::size_t>(d * ld + r)];
        const Index want = written_formula(p, row.data());
        ASSERT_EQ(index.cell_of(row.data()), want) << "row " << r;
        ASSERT_EQ(archive.index_of(row.data()), want) << "row " << r;
        ASSERT_EQ(cells[static_cast<std::size_t>(r)], want) << "row " << r << " of " << n;
      }
    }
  }
}

TEST(GridIndex, EdgesOfTheDefaultGrid) {
  const GridIndex index(params_of({100, 100}, 0.0, 1.0));
  auto cell = [&](float a, float b) {
    const Real m[2] = {a, b};
    return index.cell_of(m);
  };
  EXPECT_EQ(cell(0.0f, 0.0f), 0);
  EXPECT_EQ(cell(1.0f, 1.0f), 9999);        // the upper bound is clamped into the last bin
  EXPECT_EQ(cell(0.01f, 0.0f), 100);        // an edge lands in the upper bin
  EXPECT_EQ(cell(0.84f, 0.5f), 8450);       // 0.84f * 100 = 83.999997: the margin lifts it
  EXPECT_EQ(cell(-3.0f, 7.0f), 99);         // out of range: clamped per dimension
  EXPECT_EQ(cell(0.00999f, 0.0f), 0);
}

TEST(GridIndex, NanThrowsFromBothPaths) {
  const GridIndex index(params_of({10, 10}, 0.0, 1.0));
  const Index n = 20;
  std::vector<Real> measures_t(static_cast<std::size_t>(2 * n), 0.3f);
  measures_t[static_cast<std::size_t>(n + 11)] = std::numeric_limits<float>::quiet_NaN();  // row 11, dimension 1
  std::vector<std::int32_t> cells(static_cast<std::size_t>(n));
  EXPECT_THROW(index.cells_of_t(measures_t.data(), n, n, cells.data()), Error);
  EXPECT_NO_THROW(index.cells_of_t(measures_t.data(), n, 11, cells.data()));
  const Real m[2] = {0.5f, std::numeric_limits<float>::quiet_NaN()};
  EXPECT_THROW(index.cell_of(m), Error);
}

}  // namespace
}  // namespace qdmeta
