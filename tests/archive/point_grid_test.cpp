// The unstructured archive's neighbour index against brute force: nearest() after inserts,
// erases and new layouts (lattice points with exact ties, points beyond the grid, 1 to 5
// dimensions); what ring_spans() says it reaches; and rows_apart_from_earlier() against the
// all-pairs rule.
#include "qdmeta/archive/point_grid.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

// A point on a lattice of step 1/16 (exact ties in distance, points on cell edges), spread so
// that some lie beyond the grid's [-4, 4].
std::vector<Real> lattice_point(Rng& rng, Index d, double spread) {
  std::vector<Real> p(static_cast<std::size_t>(d));
  for (auto& x : p) x = static_cast<Real>(std::round(rng.normal() * spread * 16.0) / 16.0);
  return p;
}

std::vector<Neighbour> brute_nearest(const std::map<Index, std::vector<Real>>& points, const std::vector<Real>& q,
                                     Index count, Index excluded) {
  std::vector<Neighbour> all;
  for (const auto& [slot, p] : points)
    if (slot != excluded)
      all.push_back({float_squared_distance(p.data(), q.data(), static_cast<Index>(q.size())), slot});
  std::sort(all.begin(), all.end());
  if (static_cast<Index>(all.size()) > count) all.resize(static_cast<std::size_t>(count));
  return all;
}

void expect_same(const std::vector<Neighbour>& got, const std::vector<Neighbour>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].slot, want[i].slot) << "rank " << i;
    EXPECT_EQ(got[i].squared_distance, want[i].squared_distance) << "rank " << i;
  }
}

TEST(PointGrid, NeighbourKeysOrderAsDistanceThenSlot) {
  EXPECT_LT(neighbour_key(0.0f, 7), neighbour_key(1e-30f, 0));
  EXPECT_LT(neighbour_key(0.5f, 3), neighbour_key(0.5f, 4));
  EXPECT_LT(neighbour_key(0.5f, 99), neighbour_key(0.50001f, 0));
  EXPECT_LT(neighbour_key(3e38f, 1), neighbour_key(std::numeric_limits<Real>::infinity(), 0));
  EXPECT_EQ(key_slot(neighbour_key(2.0f, 123456)), 123456);
  EXPECT_EQ(key_squared_distance(neighbour_key(2.25f, 5)), 2.25f);
  NearestKeys best;
  best.reset(3);
  for (const NeighbourKey k : {neighbour_key(4, 1), neighbour_key(1, 9), neighbour_key(9, 0), neighbour_key(1, 2),
                               neighbour_key(0.5f, 8)})
    best.offer(k);
  ASSERT_EQ(best.size(), 3u);
  EXPECT_EQ(best[0], neighbour_key(0.5f, 8));
  EXPECT_EQ(best[1], neighbour_key(1, 2));
  EXPECT_EQ(best[2], neighbour_key(1, 9));
  EXPECT_EQ(best.bar(), 1.0f);
}

TEST(PointGrid, NearestMatchesBruteForceThroughInsertsErasesAndNewLayouts) {
  for (const Index d : {1, 2, 3, 4, 5}) {
    for (const double spread : {0.3, 1.0, 3.0}) {
      PointGrid grid(d);
      std::map<Index, std::vector<Real>> present;
      Rng rng(static_cast<std::uint64_t>(100 * d) + static_cast<std::uint64_t>(spread * 10));
      Index next_slot = 0;
      std::vector<Neighbour> got;
      for (int step = 0; step < 1500; ++step) {
        const double u = rng.uniform();
        if (u < 0.55 || present.size() < 5) {  // insert (a few slots are reused after an erase)
          const auto p = lattice_point(rng, d, spread);
          grid.insert(next_slot, p.data());
          present[next_slot++] = p;
        } else if (u < 0.75) {  // erase one, or move one as a replacement does
          auto it = present.begin();
          std::advance(it, static_cast<long>(rng.below(present.size())));
          grid.erase(it->first);
          if (rng.uniform() < 0.5) {
            it->second = lattice_point(rng, d, spread);
            grid.insert(it->first, it->second.data());
          } else {
            present.erase(it);
          }
        } else {  // query
          const auto q = lattice_point(rng, d, spread);
          const auto count = static_cast<Index>(1 + rng.below(20));
          Index excluded = -1;
          if (rng.uniform() < 0.5) {
            auto it = present.begin();
            std::advance(it, static_cast<long>(rng.below(present.size())));
            excluded = it->first;
          }
          grid.nearest(q.data(), count, excluded, got);
          SCOPED_TRACE(testing::Message() << "d = " << d << ", spread = " << spread << ", step " << step);
          expect_same(got, brute_nearest(present, q, count, excluded));
        }
        ASSERT_EQ(grid.size(), static_cast<Index>(present.size()));
      }
    }
  }
}

TEST(PointGrid, ManyPointsInOneCellForceNewLayoutsAndStayFindable) {
  PointGrid grid(2);
  std::map<Index, std::vector<Real>> present;
  Rng rng(3);
  for (Index s = 0; s < 300; ++s) {  // all in the cell at the origin, then a few far away
    std::vector<Real> p = {static_cast<Real>(rng.uniform(0, 0.06)), static_cast<Real>(rng.uniform(0, 0.06))};
    if (s % 50 == 0) p = {static_cast<Real>(rng.uniform(-9, 9)), static_cast<Real>(rng.uniform(-9, 9))};
    grid.insert(s, p.data());
    present[s] = p;
  }
  std::vector<Neighbour> got;
  for (int i = 0; i < 50; ++i) {
    const std::vector<Real> q = {static_cast<Real>(rng.uniform(-1, 1)), static_cast<Real>(rng.uniform(-1, 1))};
    grid.nearest(q.data(), 40, -1, got);
    expect_same(got, brute_nearest(present, q, 40, -1));
  }
}

TEST(PointGrid, ReserveLaysOutForABatchAndEmptiesTheGrid) {
  PointGrid grid(2);
  const Real old[2] = {0.1f, 0.1f};
  grid.insert(0, old);
  Rng rng(4);
  std::vector<Real> batch;
  for (int i = 0; i < 400; ++i) batch.push_back(static_cast<Real>(rng.normal() * 0.05));
  grid.reserve(batch.data(), 200);
  EXPECT_EQ(grid.size(), 0);
  std::map<Index, std::vector<Real>> present;
  for (Index s = 0; s < 200; ++s) {
    grid.insert(s, batch.data() + 2 * s);
    present[s] = {batch[static_cast<std::size_t>(2 * s)], batch[static_cast<std::size_t>(2 * s + 1)]};
  }
  std::vector<Neighbour> got;
  grid.nearest(old, 16, -1, got);
  expect_same(got, brute_nearest(present, {old[0], old[1]}, 16, -1));
}

TEST(PointGrid, RingsReachEveryPointCloserThanTheyClaim) {
  PointGrid grid(2);
  std::vector<std::vector<Real>> points;
  Rng rng(5);
  for (Index s = 0; s < 2000; ++s) {
    points.push_back(lattice_point(rng, 2, 1.5));
    grid.insert(s, points.back().data());
  }
  for (int i = 0; i < 100; ++i) {
    const auto q = lattice_point(rng, 2, 1.5);
    std::vector<PointGrid::Span> spans;
    for (int r = 0; r < 6; ++r) {
      const double reach = grid.ring_spans(q.data(), r, spans);
      NearestKeys all;
      all.reset(points.size());
      for (const auto& span : spans) grid.offer(span, q.data(), -1, all);
      std::vector<bool> seen(points.size(), false);
      for (std::size_t k = 0; k < all.size(); ++k) seen[static_cast<std::size_t>(key_slot(all[k]))] = true;
      for (std::size_t s = 0; s < points.size(); ++s) {
        if (std::sqrt(static_cast<double>(float_squared_distance(points[s].data(), q.data(), 2))) < reach) {
          ASSERT_TRUE(seen[s]) << "point " << s << " within the reach " << reach << " of ring " << r;
        }
      }
    }
  }
}

std::vector<std::uint8_t> brute_apart(const std::vector<Real>& points, Index count, Index d, double radius) {
  std::vector<std::uint8_t> apart(static_cast<std::size_t>(count), 1);
  for (Index i = 0; i < count; ++i)
    for (Index j = 0; j < i; ++j)
      if (!(std::sqrt(static_cast<double>(float_squared_distance(points.data() + j * d, points.data() + i * d, d))) >
            radius))
        apart[static_cast<std::size_t>(i)] = 0;
  return apart;
}

TEST(PointGrid, RowsApartFromEarlierFollowsTheAllPairsRuleOnAnyThreadCount) {
  for (const Index d : {1, 2, 3}) {
    for (const double radius : {0.0, 0.02, 0.0625, 0.3, 5.0}) {
      Rng rng(static_cast<std::uint64_t>(d) * 7 + static_cast<std::uint64_t>(radius * 1000));
      std::vector<Real> points;
      for (int i = 0; i < 1500; ++i) {
        const auto p = lattice_point(rng, d, i % 100 == 0 ? 30.0 : 0.8);  // a few far outliers
        points.insert(points.end(), p.begin(), p.end());
      }
      // Exact distances of `radius` on the lattice: ties with the threshold.
      const Index count = 1500;
      const auto want = brute_apart(points, count, d, radius);
      std::vector<std::uint8_t> one, two;
      tbb::task_arena(1).execute([&] { one = rows_apart_from_earlier(points.data(), count, d, radius); });
      tbb::task_arena(2).execute([&] { two = rows_apart_from_earlier(points.data(), count, d, radius); });
      EXPECT_EQ(one, want) << "d = " << d << ", radius " << radius;
      EXPECT_EQ(two, want) << "d = " << d << ", radius " << radius;
      // Both answers occur.
      const auto kept = std::count(want.begin(), want.end(), std::uint8_t{1});
      EXPECT_GT(kept, 1);
      EXPECT_LT(kept, count);
    }
  }
  const Real points[4] = {0.0f, 1.0f, 1.0f, 3.0f};  // 1-D
  EXPECT_EQ(rows_apart_from_earlier(points, 4, 1, 0.0), (std::vector<std::uint8_t>{1, 1, 0, 1}));
  EXPECT_EQ(rows_apart_from_earlier(points, 4, 1, -1.0), (std::vector<std::uint8_t>{1, 1, 1, 1}));
  EXPECT_EQ(rows_apart_from_earlier(points, 4, 1, std::numeric_limits<double>::infinity()),
            (std::vector<std::uint8_t>{1, 0, 0, 0}));
  EXPECT_EQ(rows_apart_from_earlier(points, 4, 1, std::nan("")), (std::vector<std::uint8_t>{1, 0, 0, 0}));
  EXPECT_TRUE(rows_apart_from_earlier(points, 0, 1, 1.0).empty());
}

}  // namespace
}  // namespace qdmeta
