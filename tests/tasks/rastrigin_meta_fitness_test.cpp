// Rastrigin meta-fitnesses (docs/specification.md, Meta-objectives) against a straightforward double-precision
// computation written here (per solution, plain loops, std::cos), on the same sample: the
// objectives document their draw order, so the reference reproduces it from the same seed.
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {
namespace {

constexpr double kM = 2000.0;
constexpr int kN = 20;

RowMatrix random_archive(Index rows, Index cols, std::uint64_t seed) {
  Rng rng(seed);
  RowMatrix g(rows, cols);
  for (Index k = 0; k < g.size(); ++k) g.data()[k] = static_cast<Real>(rng.uniform());
  return g;
}

double ref_x(Real g) { return -5.12 + 10.24 * static_cast<double>(g); }
double ref_term(double x) { return x * x - 10.0 * std::cos(2.0 * std::numbers::pi * x); }
double ref_score(double f, double m) { return m + std::max(-m, f); }

// Dimension meta-fitness of the rows `sample` of `e`.
double ref_dimension(const RowMatrix& e, const std::vector<Index>& sample, const std::vector<int>& dims, double m) {
  const Index n_genes = e.cols();
  double quality = 0.0;
  for (int j : dims)
    for (Index s : sample) {
      double sum = 0.0;
      for (Index i = 0; i < n_genes; ++i)
        if (i != j) sum += ref_term(ref_x(e(s, i)));
      quality += ref_score(-(10.0 * static_cast<double>(n_genes - 1) + sum), m);
    }
  double diversity = 0.0;
  const auto n = sample.size();
  if (n >= 2) {
    double pairs = 0.0;
    for (std::size_t s = 0; s < n; ++s)
      for (std::size_t t = s + 1; t < n; ++t) {
        double d2 = 0.0;
        for (Index i = 0; i < n_genes; ++i) {
          const double d = static_cast<double>(e(sample[s], i)) - static_cast<double>(e(sample[t], i));
          d2 += d * d;
        }
        pairs += std::sqrt(d2);
      }
    diversity = std::sqrt(static_cast<double>(n_genes)) * m / static_cast<double>(n - 1) * pairs;
  }
  return (quality + diversity) / static_cast<double>(dims.size());
}

// Score of one solution under x' = a x + b: 0 when out of range.
double ref_translated_score(const RowMatrix& e, Index s, const rastrigin::LinearTransform& t, double m) {
  double sum = 0.0;
  for (Index i = 0; i < e.cols(); ++i) {
    const double x = t.a * ref_x(e(s, i)) + t.b;
    if (std::abs(x) > 5.12) return 0.0;
    sum += ref_term(x);
  }
  return ref_score(-(10.0 * static_cast<double>(e.cols()) + sum), m);
}

struct RefTranslation {
  double value = 0.0;
  int in_range = 0;      // (solution, transform) pairs scored normally
  int out_of_range = 0;  // pairs that scored 0
};

// Translation meta-fitness, reproducing the documented draws: the sample, then the transforms.
RefTranslation ref_translation(const RowMatrix& e, const RastriginMetaParams& p, std::uint64_t seed) {
  Rng rng(seed);
  const auto sample = sample_elites(e.rows(), meta_sample_size(p.sample_fraction, e.rows()), rng);
  std::vector<std::vector<rastrigin::LinearTransform>> sets;
  if (p.transform_per_solution)
    for (std::size_t s = 0; s < sample.size(); ++s) sets.push_back(rastrigin::sample_meta_transforms(rng, p.transform_repetitions));
  else
    sets.push_back(rastrigin::sample_meta_transforms(rng, p.transform_repetitions));
  RefTranslation out;
  const std::size_t tasks = sets[0].size();
  for (std::size_t k = 0; k < tasks; ++k)
    for (std::size_t s = 0; s < sample.size(); ++s) {
      const auto& t = sets[p.transform_per_solution ? s : 0][k];
      const double score = ref_translated_score(e, sample[s], t, p.score_m);
      (score == 0.0 ? out.out_of_range : out.in_range) += 1;
      out.value += score;
    }
  out.value /= static_cast<double>(tasks);
  return out;
}

std::vector<Index> reproduce_sample(Index rows, double fraction, std::uint64_t seed) {
  Rng rng(seed);
  return sample_elites(rows, meta_sample_size(fraction, rows), rng);
}

void expect_rel_near(double actual, double expected, double rel) {
  EXPECT_NEAR(actual, expected, rel * std::abs(expected)) << "relative error " << (actual - expected) / expected;
}

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError thrown)";
}

std::vector<int> first_dims(int count) {
  std::vector<int> d(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) d[static_cast<std::size_t>(k)] = k;
  return d;
}

// ---------------------------------------------------------------- parameters

TEST(RastriginMetaParams, DefaultsAreValidAndMatchTheSpec) {
  const RastriginMetaParams p;
  EXPECT_NO_THROW(p.validate());
  EXPECT_EQ(p.sample_fraction, 0.10);
  EXPECT_EQ(p.score_m, 2000.0);
  EXPECT_EQ(p.dimension_count, 10);
  EXPECT_EQ(p.transform_repetitions, 2);
  EXPECT_FALSE(p.transform_per_solution);
  EXPECT_EQ(RastriginTranslationMeta(p).transform_count(), 16);
}

TEST(RastriginMetaParams, ValidateNamesFieldValueAndRule) {
  auto msg = [](auto change) {
    RastriginMetaParams p;
    change(p);
    return message_of([&] { p.validate(); });
  };
  EXPECT_EQ(msg([](auto& p) { p.sample_fraction = 0.0; }), "meta_fitness.sample_fraction = 0 is out of range: must be in (0, 1]");
  EXPECT_EQ(msg([](auto& p) { p.sample_fraction = 1.5; }), "meta_fitness.sample_fraction = 1.5 is out of range: must be in (0, 1]");
  EXPECT_EQ(msg([](auto& p) { p.sample_fraction = std::nan(""); }),
            "meta_fitness.sample_fraction = nan is out of range: must be in (0, 1]");
  EXPECT_EQ(msg([](auto& p) { p.score_m = 0.0; }), "score_m = 0 is out of range: must be positive and finite");
  EXPECT_EQ(msg([](auto& p) { p.score_m = INFINITY; }), "score_m = inf is out of range: must be positive and finite");
  EXPECT_EQ(msg([](auto& p) { p.dimension_count = 0; }),
            "meta_fitness.dimension_count = 0 is out of range: must be in [1, 10000]");
  EXPECT_EQ(msg([](auto& p) { p.transform_repetitions = -1; }),
            "meta_fitness.transform_repetitions = -1 is out of range: must be in [1, 1000]");
}

TEST(RastriginMetaParams, ConstructorsValidate) {
  RastriginMetaParams bad;
  bad.sample_fraction = 2.0;
  EXPECT_THROW(RastriginTranslationMeta{bad}, InputError);
  EXPECT_THROW(RastriginDimensionMeta(bad, first_dims(10)), InputError);
}

TEST(RastriginDimensionMeta, RejectsBadDimensions) {
  const RastriginMetaParams p;
  EXPECT_EQ(message_of([&] { RastriginDimensionMeta(p, first_dims(9)); }),
            "rastrigin-dimension meta-fitness: 9 dimensions given, dimension_count = 10");
  EXPECT_EQ(message_of([&] { RastriginDimensionMeta(p, {0, 1, 2, 3, 4, 5, 6, 7, 8, 3}); }),
            "rastrigin-dimension meta-fitness: dimension 3 is repeated");
  EXPECT_EQ(message_of([&] { RastriginDimensionMeta(p, {0, 1, 2, 3, 4, 5, 6, 7, 8, -1}); }),
            "rastrigin-dimension meta-fitness: dimension -1 is negative");
  const RastriginDimensionMeta meta(p, {0, 1, 2, 3, 4, 5, 6, 7, 8, 25});
  const RowMatrix e = random_archive(10, kN, 1);
  Rng rng(1);
  SerialEvaluator ev;
  EXPECT_EQ(message_of([&] { meta.evaluate(e, rng, ev); }),
            "rastrigin-dimension meta-fitness: dimension 25 is outside a genotype of size 20");
}

// ---------------------------------------------------------------- sampling

TEST(MetaSampleSize, RoundsAndKeepsAtLeastOne) {
  EXPECT_EQ(meta_sample_size(0.1, 15), 2);  // 1.5 rounds up
  EXPECT_EQ(meta_sample_size(0.1, 4), 1);   // 0.4 rounds to 0, at least 1
  EXPECT_EQ(meta_sample_size(0.1, 14), 1);
  EXPECT_EQ(meta_sample_size(0.1, 10000), 1000);
  EXPECT_EQ(meta_sample_size(0.1, 1), 1);
  EXPECT_EQ(meta_sample_size(1.0, 37), 37);
  EXPECT_EQ(meta_sample_size(0.1, 0), 0);  // empty archive: nothing to sample
}

TEST(SampleElites, DistinctInRangeAndDeterministic) {
  Rng a(7), b(7), c(8);
  const auto sa = sample_elites(1000, 100, a);
  const auto sb = sample_elites(1000, 100, b);
  const auto sc = sample_elites(1000, 100, c);
  EXPECT_EQ(sa, sb);
  EXPECT_NE(sa, sc);
  ASSERT_EQ(sa.size(), 100u);
  EXPECT_EQ(std::set<Index>(sa.begin(), sa.end()).size(), 100u);
  for (Index i : sa) {
    EXPECT_GE(i, 0);
    EXPECT_LT(i, 1000);
  }
  EXPECT_EQ(a.state(), b.state());  // same number of draws
}

TEST(SampleElites, FullFractionCoversEveryRow) {
  Rng rng(3);
  auto s = sample_elites(37, meta_sample_size(1.0, 37), rng);
  std::sort(s.begin(), s.end());
  for (Index i = 0; i < 37; ++i) EXPECT_EQ(s[static_cast<std::size_t>(i)], i);
  Rng rng2(3);
  EXPECT_TRUE(sample_elites(0, 0, rng2).empty());
}

TEST(SampleElites, IsUniform) {
  Rng rng(11);
  std::vector<int> hits(10, 0);
  const int trials = 20000;
  for (int t = 0; t < trials; ++t)
    for (Index i : sample_elites(10, 3, rng)) ++hits[static_cast<std::size_t>(i)];
  for (int h : hits) EXPECT_NEAR(h / static_cast<double>(trials), 0.3, 0.015);  // SD ~0.0032
}

TEST(SampleElites, RejectsTooLargeSample) {
  Rng rng(1);
  EXPECT_EQ(message_of([&] { sample_elites(4, 5, rng); }), "cannot sample 5 distinct elites out of an archive of 4");
}

// ---------------------------------------------------------------- pairwise distances

TEST(PairwiseDistanceSum, MatchesTheStraightforwardDoubleSum) {
  for (Index rows : {0, 1, 2, 5, 37, 300, 600}) {  // row lengths below, at and past the four lanes
    const RowMatrix p = random_archive(rows, kN, 5 + static_cast<std::uint64_t>(rows));
    double expected = 0.0;
    for (Index s = 0; s < rows; ++s)
      for (Index t = s + 1; t < rows; ++t)
        expected += (p.row(s).cast<double>() - p.row(t).cast<double>()).norm();
    const double got = pairwise_distance_sum(p);
    if (rows < 2) {
      EXPECT_EQ(got, 0.0);
    } else {
      expect_rel_near(got, expected, 1e-10);
    }
  }
}

TEST(PairwiseDistanceSum, GivesThePortableLoopsBitsAtEverySize) {
  // Row counts around the vector steps (4 lanes, 16 rows a step), several widths.
  for (const Index cols : {1, 3, kN}) {
    for (Index rows = 0; rows <= 70; ++rows) {
      const RowMatrix p = random_archive(rows, cols, 40 + static_cast<std::uint64_t>(rows * cols));
      EXPECT_EQ(pairwise_distance_sum(p), pairwise_distance_sum_portable(p)) << rows << " x " << cols;
    }
    for (const Index rows : {255, 256, 257, 1000}) {
      const RowMatrix p = random_archive(rows, cols, 7 + static_cast<std::uint64_t>(rows));
      EXPECT_EQ(pairwise_distance_sum(p), pairwise_distance_sum_portable(p)) << rows << " x " << cols;
    }
  }
}

TEST(PairwiseDistanceSum, IdenticalRowsGiveExactlyZero) {
  RowMatrix p(50, kN);
  Rng rng(2);
  for (Index i = 0; i < kN; ++i) p.col(i).setConstant(static_cast<Real>(rng.uniform()));
  const double d = pairwise_distance_sum(p);
  EXPECT_TRUE(std::isfinite(d));
  EXPECT_EQ(d, 0.0);  // differences, not |a|^2 + |b|^2 - 2 a.b: no rounding residue
}

// ---------------------------------------------------------------- Dimension meta-fitness

class DimensionVsReference : public testing::TestWithParam<std::tuple<Index, double>> {};

TEST_P(DimensionVsReference, MatchesStraightforwardComputation) {
  const auto [rows, fraction] = GetParam();
  RastriginMetaParams p;
  p.sample_fraction = fraction;
  Rng dim_rng(99);
  const auto dims = rastrigin::sample_dimensions(dim_rng, kN, p.dimension_count);
  const RastriginDimensionMeta meta(p, dims);
  const RowMatrix e = random_archive(rows, kN, 1000 + static_cast<std::uint64_t>(rows));
  SerialEvaluator ev;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    Rng rng(seed);
    const auto r = meta.evaluate(e, rng, ev);
    const auto sample = reproduce_sample(rows, fraction, seed);
    expect_rel_near(r.value, ref_dimension(e, sample, dims, kM), 1e-6);
    EXPECT_EQ(r.evaluations, static_cast<std::int64_t>(sample.size()) * 10);
  }
}

INSTANTIATE_TEST_SUITE_P(Archives, DimensionVsReference,
                         testing::Combine(testing::Values<Index>(5, 37, 200), testing::Values(0.1, 0.5, 1.0)));

TEST(RastriginDimensionMeta, KnownAnswer) {
  // Row 0: x = 0 everywhere (f = 0). Row 1: x_0 = 1 (g = 153/256), term +1, so f_0 = 0 and
  // f_j = -1 otherwise. Distance 25/256; n = 2, alpha = sqrt(20) M.
  RowMatrix e = RowMatrix::Constant(2, kN, 0.5f);
  e(1, 0) = 153.0f / 256.0f;
  RastriginMetaParams p;
  p.sample_fraction = 1.0;
  const RastriginDimensionMeta meta(p, first_dims(10));
  Rng rng(1);
  SerialEvaluator ev;
  const auto r = meta.evaluate(e, rng, ev);
  const double quality = 10 * kM + kM + 9 * (kM - 1);
  const double diversity = std::sqrt(20.0) * kM * 25.0 / 256.0;
  expect_rel_near(r.value, (quality + diversity) / 10.0, 1e-7);
  EXPECT_EQ(r.evaluations, 20);
}

TEST(RastriginDimensionMeta, SingleSampleHasNoDiversityTermAndNoNan) {
  RastriginMetaParams p;  // fraction 0.1 of 5 rows -> n = 1
  const auto dims = first_dims(10);
  const RastriginDimensionMeta meta(p, dims);
  const RowMatrix e = random_archive(5, kN, 4);
  Rng rng(5);
  SerialEvaluator ev;
  const auto r = meta.evaluate(e, rng, ev);
  ASSERT_TRUE(std::isfinite(r.value));
  EXPECT_EQ(r.evaluations, 10);
  const auto sample = reproduce_sample(5, 0.1, 5);
  ASSERT_EQ(sample.size(), 1u);
  double quality = 0.0;  // one solution: F is its mean score over J
  for (int j : dims) quality += ref_score(rastrigin::without_dimension({e.row(sample[0]).data(), kN}, j), kM);
  expect_rel_near(r.value, quality / 10.0, 1e-6);
}

TEST(RastriginDimensionMeta, IdenticalElitesGiveNoNan) {
  RowMatrix e(30, kN);
  Rng g(6);
  for (Index i = 0; i < kN; ++i) e.col(i).setConstant(static_cast<Real>(g.uniform()));
  RastriginMetaParams p;
  p.sample_fraction = 1.0;
  const RastriginDimensionMeta meta(p, first_dims(10));
  Rng rng(1);
  SerialEvaluator ev;
  const auto r = meta.evaluate(e, rng, ev);
  ASSERT_TRUE(std::isfinite(r.value));
  expect_rel_near(r.value, ref_dimension(e, reproduce_sample(30, 1.0, 1), first_dims(10), kM), 1e-6);
}

TEST(RastriginDimensionMeta, EmptyArchiveScoresZero) {
  const RastriginDimensionMeta meta(RastriginMetaParams{}, first_dims(10));
  Rng rng(1);
  SerialEvaluator ev;
  const auto r = meta.evaluate(RowMatrix(0, kN), rng, ev);
  EXPECT_EQ(r.value, 0.0);
  EXPECT_EQ(r.evaluations, 0);
}

// ---------------------------------------------------------------- Translation meta-fitness

class TranslationVsReference : public testing::TestWithParam<std::tuple<Index, double, bool>> {};

TEST_P(TranslationVsReference, MatchesStraightforwardComputation) {
  const auto [rows, fraction, per_solution] = GetParam();
  RastriginMetaParams p;
  p.sample_fraction = fraction;
  p.transform_per_solution = per_solution;
  const RastriginTranslationMeta meta(p);
  const RowMatrix e = random_archive(rows, kN, 2000 + static_cast<std::uint64_t>(rows));
  SerialEvaluator ev;
  int in_range = 0, out_of_range = 0;
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    Rng rng(seed);
    const auto r = meta.evaluate(e, rng, ev);
    const auto ref = ref_translation(e, p, seed);
    expect_rel_near(r.value, ref.value, 1e-6);
    EXPECT_EQ(r.evaluations, static_cast<std::int64_t>(meta_sample_size(fraction, rows)) * 16);
    in_range += ref.in_range;
    out_of_range += ref.out_of_range;
  }
  if (rows >= 37) {  // both branches of the out-of-range rule were exercised
    EXPECT_GT(in_range, 0);
    EXPECT_GT(out_of_range, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Archives, TranslationVsReference,
                         testing::Combine(testing::Values<Index>(5, 37, 200), testing::Values(0.1, 1.0),
                                          testing::Bool()));

TEST(RastriginTranslationMeta, OutOfRangeScoresZero) {
  // Rows mixing genes at 0 and 1 (x = -5.12 and 5.12): an expanding transform (|a| > 1) maps
  // one of them beyond 5.12, so every expanding transform scores 0.
  RowMatrix e(6, kN);
  for (Index r = 0; r < e.rows(); ++r)
    for (Index i = 0; i < kN; ++i) e(r, i) = (i + r) % 3 == 0 ? 1.0f : 0.0f;
  RastriginMetaParams p;
  p.sample_fraction = 1.0;
  const RastriginTranslationMeta meta(p);
  SerialEvaluator ev;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    Rng rng(seed);
    const auto r = meta.evaluate(e, rng, ev);
    Rng replay(seed);
    const auto sample = sample_elites(6, 6, replay);
    const auto transforms = rastrigin::sample_meta_transforms(replay, 2);
    double expected = 0.0;
    for (const auto& t : transforms) {
      const bool expand = std::abs(t.a) > 1.0;
      for (Index s : sample) {
        const double score = ref_translated_score(e, s, t, kM);
        if (expand) {
          EXPECT_EQ(score, 0.0);
        }
        expected += score;
      }
      if (expand) {  // the objective agrees: scoring this transform alone gives 0
        EXPECT_FALSE(rastrigin::translated({e.row(0).data(), kN}, t.a, t.b).has_value());
      }
    }
    expect_rel_near(r.value, expected / 16.0, 1e-6);
    EXPECT_LE(r.value, 8.0 * 6.0 * kM / 16.0);  // at most the 8 shrinking transforms contribute
  }
  // A single row of all-ones under x' = a x + b with a expanding and b >= 0 is out of range.
  const RowMatrix ones = RowMatrix::Ones(1, kN);
  EXPECT_FALSE(rastrigin::translated({ones.data(), kN}, 1.05, 0.1).has_value());
}

TEST(RastriginTranslationMeta, EvaluationsCountTransforms) {
  RastriginMetaParams p;
  p.transform_repetitions = 3;
  const RastriginTranslationMeta meta(p);
  EXPECT_EQ(meta.transform_count(), 24);
  const RowMatrix e = random_archive(150, kN, 8);
  Rng rng(1);
  SerialEvaluator ev;
  EXPECT_EQ(meta.evaluate(e, rng, ev).evaluations, 15 * 24);
}

// ---------------------------------------------------------------- shared properties

// Archive-summed: an archive plus a copy of it, each row nudged so all rows are distinct,
// scores about twice as much. Genes in [0.25, 0.75] keep every transform in range (|x'| < 3.4),
// so the different transforms that the two evaluations draw move the ratio by well under 1%
// (measured: 1.999-2.004 over seeds 1-5).
TEST(RastriginMeta, ArchiveSummedDoublingAnArchiveDoublesTheScore) {
  RowMatrix e = random_archive(200, kN, 9);
  e = (0.25f + 0.5f * e.array()).matrix();
  RowMatrix doubled(400, kN);
  doubled.topRows(200) = e;
  Rng nudge(10);
  for (Index r = 0; r < 200; ++r)
    for (Index i = 0; i < kN; ++i)
      doubled(200 + r, i) =
          std::clamp(e(r, i) + static_cast<Real>(1e-4 * (nudge.uniform() - 0.5)), 0.0f, 1.0f);
  RastriginMetaParams p;
  p.sample_fraction = 1.0;  // no sampling noise
  SerialEvaluator ev;

  const RastriginTranslationMeta translation(p);
  Rng r1(1), r2(1);
  const double single_t = translation.evaluate(e, r1, ev).value;
  const double double_t = translation.evaluate(doubled, r2, ev).value;
  EXPECT_NEAR(double_t / single_t, 2.0, 0.02);

  // Dimension: the quality term doubles; so does the diversity term (alpha ~ 1/n, pairs ~ n^2).
  const RastriginDimensionMeta dimension(p, first_dims(10));
  Rng r3(1), r4(1);
  const double single_d = dimension.evaluate(e, r3, ev).value;
  const double double_d = dimension.evaluate(doubled, r4, ev).value;
  EXPECT_NEAR(double_d / single_d, 2.0, 0.02);
}

TEST(RastriginMeta, DeterministicGivenTheSeed) {
  const RowMatrix e = random_archive(500, kN, 12);
  const RastriginDimensionMeta dimension(RastriginMetaParams{}, first_dims(10));
  RastriginMetaParams per;
  per.transform_per_solution = true;
  const RastriginTranslationMeta shared(RastriginMetaParams{}), per_solution(per);
  SerialEvaluator ev;
  for (const MetaObjective* m : std::initializer_list<const MetaObjective*>{&dimension, &shared, &per_solution}) {
    Rng a(21), b(21), c(22);
    const double va = m->evaluate(e, a, ev).value;
    EXPECT_EQ(va, m->evaluate(e, b, ev).value) << m->name();
    EXPECT_EQ(a.state(), b.state()) << m->name();
    EXPECT_NE(va, m->evaluate(e, c, ev).value) << m->name();  // a fresh sample each evaluation
  }
  EXPECT_EQ(dimension.name(), "rastrigin-dimension");
  EXPECT_EQ(shared.name(), "rastrigin-translation");
}

}  // namespace
}  // namespace qdmeta
