// AURORA's unstructured archive: the insertion rule on hand-built cases (far -> added, too close
// to the second nearest -> rejected, eps-dominating -> replaces in place, dominated -> rejected),
// eps-dominance with negative fitness, novelty against a brute-force reference, and statistics.
#include "qdmeta/archive/unstructured_archive.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "expect_input_error.hpp"

namespace qdmeta {
namespace {

UnstructuredArchiveParams params2d() {
  UnstructuredArchiveParams p;
  p.measure_size = 2;
  p.solution_size = 1;
  p.base_feature_size = 1;
  p.target_size = 4;
  p.eps = 0.1;
  p.novelty_neighbours = 15;
  p.qd_offset = -100;
  return p;
}

// Adds a member whose solution and base feature are `id`, to tell members apart.
AddStatus put(UnstructuredArchive& a, float x, float y, float fitness, float id, double l = 1.0) {
  const Real d[2] = {x, y};
  return a.add(&id, fitness, d, &id, l);
}

TEST(UnstructuredArchive, FarFromEveryMemberIsAdded) {
  UnstructuredArchive a(params2d());
  EXPECT_EQ(put(a, 0, 0, -10, 1), AddStatus::kNew);  // empty
  EXPECT_EQ(put(a, 2, 0, -10, 2), AddStatus::kNew);  // 2 > l = 1
  EXPECT_EQ(put(a, 5, 0, -10, 3), AddStatus::kNew);
  EXPECT_EQ(a.size(), 3);
  EXPECT_EQ(a.descriptor(2, 0), 5.0f);
  EXPECT_EQ(*a.solution(1), 2.0f);
}

TEST(UnstructuredArchive, TooCloseToTheOnlyMemberIsRejectedWhateverItsFitness) {
  UnstructuredArchive a(params2d());
  put(a, 0, 0, -10, 1);
  EXPECT_EQ(put(a, 0.5f, 0, 1000, 2), AddStatus::kNotAdded);
  EXPECT_EQ(a.size(), 1);
  EXPECT_EQ(*a.solution(0), 1.0f);
}

TEST(UnstructuredArchive, TooCloseToTheSecondNearestIsRejectedWhateverItsFitness) {
  UnstructuredArchive a(params2d());
  put(a, 0, 0, -10, 1);
  put(a, 1.5f, 0, -10, 2);
  // Nearest and second nearest both at 0.75 < (1 - eps) l = 0.9.
  EXPECT_EQ(put(a, 0.75f, 0, 1000, 3), AddStatus::kNotAdded);
  EXPECT_EQ(a.size(), 2);
  EXPECT_EQ(*a.solution(0), 1.0f);
  EXPECT_EQ(*a.solution(1), 2.0f);
}

TEST(UnstructuredArchive, AnEpsDominatingCandidateReplacesTheNearestInItsSlot) {
  UnstructuredArchive a(params2d());
  put(a, 0, 0, -10, 1);
  put(a, 2, 0, -10, 2);
  put(a, 5, 0, -10, 3);
  // Candidate at (-0.5, 0): nearest (0,0) at 0.5 <= l, second nearest at 2.5 >= 0.9.
  // Novelty of the candidate without the nearest: (2.5 + 5.5) / 2 = 4; of (0,0): (2 + 5) / 2 = 3.5.
  // Fitness -5 >= 1.1 x -10, novelty 4 >= 0.9 x 3.5, and (-5 + 10) 3.5 > -(4 - 3.5) 10.
  EXPECT_DOUBLE_EQ(a.member_novelty(0), 3.5);
  EXPECT_EQ(put(a, -0.5f, 0, -5, 4), AddStatus::kImproved);
  EXPECT_EQ(a.size(), 3);
  EXPECT_EQ(*a.solution(0), 4.0f);
  EXPECT_EQ(*a.base_features(0), 4.0f);
  EXPECT_EQ(a.objective(0), -5.0f);
  EXPECT_EQ(a.descriptor(0, 0), -0.5f);
}

TEST(UnstructuredArchive, ADominatedCandidateIsRejected) {
  UnstructuredArchive a(params2d());
  put(a, -0.5f, 0, -5, 1);
  put(a, 2, 0, -10, 2);
  put(a, 5, 0, -10, 3);
  // Candidate at (0.3, 0): nearest (-0.5, 0) at 0.8, second at 1.7. Fitness -50 < 1.1 x -5.
  EXPECT_EQ(put(a, 0.3f, 0, -50, 4), AddStatus::kNotAdded);
  // Fitter but much less novel: novelty (1.7 + 4.7) / 2 = 3.2 < 0.9 x 4 = 3.6.
  EXPECT_EQ(put(a, 0.3f, 0, -4.9f, 5), AddStatus::kNotAdded);
  EXPECT_EQ(*a.solution(0), 1.0f);
}

TEST(UnstructuredArchive, EpsDominanceLoosensTowardTheWorseSideForEitherSign) {
  // Negative fitness: 10% worse is still within reach (-11 >= 1.1 x -10), 10.1% is not.
  EXPECT_TRUE(eps_dominates(-10.5, 2.0, -10.0, 1.0, 0.1));
  EXPECT_FALSE(eps_dominates(-11.01, 5.0, -10.0, 1.0, 0.1));
  // Positive fitness: at least 0.9 x the member's.
  EXPECT_TRUE(eps_dominates(9.5, 2.0, 10.0, 1.0, 0.1));
  EXPECT_FALSE(eps_dominates(8.9, 5.0, 10.0, 1.0, 0.1));
  // Within the eps band on both, the weighted trade-off decides: a 5% loss in fitness against
  // a 10% gain in novelty passes, the reverse does not.
  EXPECT_TRUE(eps_dominates(9.5, 1.1, 10.0, 1.0, 0.1));
  EXPECT_FALSE(eps_dominates(9.0, 1.05, 10.0, 1.0, 0.1));
  // Equal scores do not dominate (strict inequality).
  EXPECT_FALSE(eps_dominates(10.0, 1.0, 10.0, 1.0, 0.1));
}

TEST(UnstructuredArchive, MemberNoveltyIsTheMeanDistanceToItsKNearest) {
  UnstructuredArchiveParams p = params2d();
  p.novelty_neighbours = 4;
  UnstructuredArchive a(p);
  Rng rng(3);
  std::vector<std::array<float, 2>> points;
  for (int i = 0; i < 40; ++i) {
    const float x = static_cast<float>(rng.uniform(0, 10)), y = static_cast<float>(rng.uniform(0, 10));
    if (put(a, x, y, 0, static_cast<float>(i), 0.01) == AddStatus::kNew) points.push_back({x, y});
  }
  ASSERT_EQ(a.size(), 40);
  for (Index s = 0; s < a.size(); ++s) {
    std::vector<double> d;
    for (Index t = 0; t < a.size(); ++t)
      if (t != s) d.push_back(std::hypot(double(points[t][0]) - points[s][0], double(points[t][1]) - points[s][1]));
    std::sort(d.begin(), d.end());
    EXPECT_NEAR(a.member_novelty(s), (d[0] + d[1] + d[2] + d[3]) / 4, 1e-5);
  }
}

// The insertion rule written the plain way: every distance computed, sorted by (distance, slot).
struct ReferenceArchive {
  Index d = 2;
  int k = 15;
  double eps = 0.1;
  std::vector<std::vector<float>> points;
  std::vector<float> fitness;
  std::vector<std::pair<float, Index>> sorted_from(const std::vector<float>& q, Index excluded) const {
    std::vector<std::pair<float, Index>> all;
    for (std::size_t s = 0; s < points.size(); ++s) {
      if (static_cast<Index>(s) == excluded) continue;
      float d2 = 0;
      for (Index j = 0; j < d; ++j) d2 += (points[s][j] - q[j]) * (points[s][j] - q[j]);
      all.push_back({d2, static_cast<Index>(s)});
    }
    std::sort(all.begin(), all.end());
    return all;
  }
  static double mean_sqrt(const std::vector<std::pair<float, Index>>& v, std::size_t from, std::size_t to) {
    double sum = 0;
    for (std::size_t i = from; i < to; ++i) sum += std::sqrt(double(v[i].first));
    return to > from ? sum / double(to - from) : 0.0;
  }
  AddStatus add(const std::vector<float>& q, float f, double l) {
    if (points.empty()) return points.push_back(q), fitness.push_back(f), AddStatus::kNew;
    const auto all = sorted_from(q, -1);
    if (std::sqrt(double(all[0].first)) > l) return points.push_back(q), fitness.push_back(f), AddStatus::kNew;
    if (all.size() == 1 || std::sqrt(double(all[1].first)) < (1 - eps) * l) return AddStatus::kNotAdded;
    const double nov_c = mean_sqrt(all, 1, std::min<std::size_t>(all.size(), k + 1));
    const Index s = all[0].second;
    const auto around = sorted_from(points[s], s);
    const double nov_m = mean_sqrt(around, 0, std::min<std::size_t>(around.size(), k));
    if (!eps_dominates(f, nov_c, fitness[s], nov_m, eps)) return AddStatus::kNotAdded;
    points[s] = q;
    fitness[s] = f;
    return AddStatus::kImproved;
  }
};

TEST(UnstructuredArchive, TheGridIndexDecidesExactlyAsABruteForceReference) {
  // (dimensions, spread): the 1-D case and the wide 2-D case put many points beyond the grid's
  // [-4, 4] (in its edge cells), queries included.
  const std::pair<Index, double> setups[] = {{1, 2.5}, {2, 1.0}, {2, 3.0}, {4, 0.4}};
  for (const auto& [d, spread] : setups) {
    UnstructuredArchiveParams p = params2d();
    p.measure_size = d;
    UnstructuredArchive a(p);
    ReferenceArchive ref;
    ref.d = d;
    Rng rng(static_cast<std::uint64_t>(d) + static_cast<std::uint64_t>(spread * 10));
    int counts[3] = {0, 0, 0};
    for (int i = 0; i < 3000; ++i) {
      // Clustered points on a lattice of step 1/16, the grid's cell side: points on cell edges
      // and exact ties in distance happen. The threshold shrinks as the archive fills.
      std::vector<float> q(static_cast<std::size_t>(d));
      for (auto& x : q) x = static_cast<float>(std::round(rng.normal() * spread * 16.0) / 16.0);
      const auto f = static_cast<float>(-std::abs(rng.normal()) * 10.0);
      const double l = 0.6 / (1.0 + i / 1000.0);
      const float id = static_cast<float>(i);
      const AddStatus expected = ref.add(q, f, l);
      ASSERT_EQ(a.add(&id, f, q.data(), &id, l), expected) << "d = " << d << ", candidate " << i;
      ++counts[static_cast<int>(expected)];
    }
    ASSERT_EQ(a.size(), static_cast<Index>(ref.points.size()));
    for (Index s = 0; s < a.size(); ++s) {
      ASSERT_EQ(a.objective(s), ref.fitness[static_cast<std::size_t>(s)]);
      for (Index j = 0; j < d; ++j) ASSERT_EQ(a.descriptor(s, j), ref.points[static_cast<std::size_t>(s)][j]);
    }
    // Every branch of the rule was taken.
    EXPECT_GT(counts[0], 30) << d;
    EXPECT_GT(counts[1], 30) << d;
    EXPECT_GT(counts[2], 30) << d;
  }
}

TEST(UnstructuredArchive, RefillLeavesTheArchiveThatAddingRowByRowLeaves) {
  // Lattice points, so that rows at exactly l from an earlier one occur; several thresholds,
  // so that rows are added, rejected and replaced; rows beyond the grid included.
  for (const Index d : {1, 2, 4}) {
    int statuses[3] = {0, 0, 0};  // over the thresholds
    for (const double l : {0.05, 0.25, 1.0}) {
      UnstructuredArchiveParams p = params2d();
      p.measure_size = d;
      p.solution_size = 3;
      p.base_feature_size = 2;
      Rng rng(static_cast<std::uint64_t>(d) * 31 + static_cast<std::uint64_t>(l * 100));
      const Index rows = 2000;
      std::vector<Real> solutions, objectives, descriptors, base;
      for (Index i = 0; i < rows; ++i) {
        for (int g = 0; g < 3; ++g) solutions.push_back(static_cast<Real>(i * 3 + g));
        for (int b = 0; b < 2; ++b) base.push_back(static_cast<Real>(-i - b));
        objectives.push_back(static_cast<Real>(-std::abs(rng.normal()) * 10.0));
        for (Index j = 0; j < d; ++j)
          descriptors.push_back(static_cast<Real>(std::round(rng.normal() * (i % 97 == 0 ? 6.0 : 1.2) * 16.0) / 16.0));
      }
      UnstructuredArchive one_by_one(p), refilled(p);
      for (Index i = 0; i < rows; ++i)
        ++statuses[static_cast<int>(one_by_one.add(solutions.data() + 3 * i, objectives[static_cast<std::size_t>(i)],
                                                   descriptors.data() + d * i, base.data() + 2 * i, l))];
      refilled.add(solutions.data(), 5.0f, descriptors.data(), base.data(), l);  // emptied by refill()
      refilled.refill(rows, solutions.data(), objectives.data(), descriptors.data(), base.data(), l);
      SCOPED_TRACE(testing::Message() << "d = " << d << ", l = " << l);
      ASSERT_EQ(refilled.size(), one_by_one.size());
      for (Index s = 0; s < refilled.size(); ++s) {
        ASSERT_EQ(refilled.objective(s), one_by_one.objective(s));
        ASSERT_EQ(*refilled.solution(s), *one_by_one.solution(s));
        ASSERT_EQ(*refilled.base_features(s), *one_by_one.base_features(s));
        for (Index j = 0; j < d; ++j) ASSERT_EQ(refilled.descriptor(s, j), one_by_one.descriptor(s, j));
      }
    }
    EXPECT_GT(statuses[static_cast<int>(AddStatus::kImproved)], 0) << d;
    EXPECT_GT(statuses[static_cast<int>(AddStatus::kNotAdded)], 0) << d;
  }
}

TEST(UnstructuredArchive, RefillStopsAtTheFirstNonFiniteDescriptorAsAddDoes) {
  UnstructuredArchive a(params2d());
  const Real solutions[4] = {1, 2, 3, 4}, objectives[4] = {-1, -1, -1, -1};
  const Real descriptors[8] = {0, 0, 5, 0, std::nanf(""), 0, 10, 0};
  EXPECT_THROW(a.refill(4, solutions, objectives, descriptors, solutions, 1.0), Error);
  ASSERT_EQ(a.size(), 2);
  EXPECT_EQ(*a.solution(1), 2.0f);
}

TEST(UnstructuredArchive, StatsUseTheTargetSizeAndTheOffset) {
  UnstructuredArchive a(params2d());  // target 4, offset -100
  EXPECT_EQ(a.stats(), ArchiveStats{});
  put(a, 0, 0, -10, 1);
  put(a, 2, 0, -30, 2);
  ArchiveStats s = a.stats();
  EXPECT_EQ(s.num_elites, 2);
  EXPECT_DOUBLE_EQ(s.coverage, 0.5);
  EXPECT_DOUBLE_EQ(s.qd_score, 90 + 70);
  EXPECT_DOUBLE_EQ(s.norm_qd_score, 160.0 / 4);
  EXPECT_DOUBLE_EQ(s.obj_max, -10);
  EXPECT_DOUBLE_EQ(s.obj_mean, -20);
  for (int i = 0; i < 4; ++i) put(a, 10.0f + 3 * i, 0, -10, 3);
  EXPECT_EQ(a.stats().num_elites, 6);
  EXPECT_DOUBLE_EQ(a.stats().coverage, 1.0);  // clamped
  a.clear();
  EXPECT_TRUE(a.empty());
}

TEST(UnstructuredArchive, UniformSamplingReachesEveryMember) {
  UnstructuredArchive a(params2d());
  for (int i = 0; i < 5; ++i) put(a, 3.0f * i, 0, 0, static_cast<float>(i));
  std::vector<int> hits(5, 0);
  Rng rng(1);
  for (int i = 0; i < 5000; ++i) ++hits[static_cast<std::size_t>(a.sample(rng))];
  for (int h : hits) EXPECT_NEAR(h, 1000, 150);
}

TEST(UnstructuredArchive, BadParametersAndDescriptorsAreErrors) {
  UnstructuredArchiveParams p = params2d();
  p.eps = 1.0;
  EXPECT_INPUT_ERROR(UnstructuredArchive{p}, "aurora.eps = 1 is out of range: must be in [0, 0.999]");
  UnstructuredArchive a(params2d());
  EXPECT_THROW(put(a, std::nanf(""), 0, 0, 1), Error);
}

}  // namespace
}  // namespace qdmeta
