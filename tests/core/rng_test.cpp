// Tests of src/qdmeta/core/rng.hpp: reproducibility, derived streams, and the distributions
// (uniform, below, normal, normal_float, geometric) checked statistically with fixed seeds and
// bounds of about 6 standard errors, so they are deterministic and still catch real bias.
#include "qdmeta/core/rng.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

namespace qdmeta {
namespace {

std::vector<std::uint64_t> draws(Rng& rng, int n) {
  std::vector<std::uint64_t> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out.push_back(rng());
  return out;
}

struct Moments {
  double mean = 0.0;
  double sd = 0.0;
  double within_one_sd = 0.0;  // fraction with |x| < 1
};

template <class Draw>
Moments moments(int n, Draw draw) {
  double sum = 0.0, sum2 = 0.0;
  int inside = 0;
  for (int i = 0; i < n; ++i) {
    const double x = draw();
    sum += x;
    sum2 += x * x;
    inside += std::abs(x) < 1.0;
  }
  Moments m;
  m.mean = sum / n;
  m.sd = std::sqrt(sum2 / n - m.mean * m.mean);
  m.within_one_sd = static_cast<double>(inside) / n;
  return m;
}

TEST(Rng, SameSeedGivesSameSequence) {
  Rng a(42), b(42);
  EXPECT_EQ(draws(a, 1000), draws(b, 1000));
}

TEST(Rng, DifferentSeedsGiveDifferentSequences) {
  Rng a(42), b(43);
  const auto da = draws(a, 100), db = draws(b, 100);
  int equal = 0;
  for (std::size_t i = 0; i < da.size(); ++i) equal += da[i] == db[i];
  EXPECT_EQ(equal, 0);
}

TEST(Rng, ReseedRestartsTheSequence) {
  Rng a(7);
  const auto first = draws(a, 50);
  a.reseed(7);
  EXPECT_EQ(draws(a, 50), first);
}

TEST(Rng, StreamsWithSameKeysAreEqual) {
  Rng a = Rng::stream(5, {1, 2, 3});
  Rng b = Rng::stream(5, {1, 2, 3});
  EXPECT_EQ(draws(a, 200), draws(b, 200));
}

TEST(Rng, StreamsWithDifferentKeysDiffer) {
  // Different last key, swapped keys, a missing key, a different seed, and the plain seeded
  // generator: every sequence's first 8 outputs must be distinct from every other's.
  std::vector<Rng> rngs = {Rng::stream(5, {1, 2}), Rng::stream(5, {1, 3}), Rng::stream(5, {2, 1}),
                           Rng::stream(5, {1}),    Rng::stream(6, {1, 2}), Rng::stream(5, {}),
                           Rng(5),                 Rng::stream(5, {1, 2, 0})};
  std::set<std::uint64_t> seen;
  std::size_t total = 0;
  for (Rng& r : rngs)
    for (std::uint64_t x : draws(r, 8)) {
      seen.insert(x);
      ++total;
    }
  EXPECT_EQ(seen.size(), total);
}

TEST(Rng, UniformIsInHalfOpenUnitInterval) {
  Rng rng(1);
  double lo = 1.0, hi = 0.0, sum = 0.0;
  constexpr int kN = 100'000;
  for (int i = 0; i < kN; ++i) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    sum += u;
  }
  EXPECT_LT(lo, 1e-3);
  EXPECT_GT(hi, 1.0 - 1e-3);
  EXPECT_NEAR(sum / kN, 0.5, 6 * std::sqrt(1.0 / 12 / kN));
}

TEST(Rng, UniformOpen0AndRange) {
  Rng rng(2);
  for (int i = 0; i < 100'000; ++i) {
    const double u = rng.uniform_open0();
    ASSERT_GT(u, 0.0);
    ASSERT_LE(u, 1.0);
    const double v = rng.uniform(-3.0, 2.0);
    ASSERT_GE(v, -3.0);
    ASSERT_LT(v, 2.0);
  }
}

TEST(Rng, BelowStaysInRange) {
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(rng.below(1), 0u);
  const std::uint64_t big = (std::uint64_t{1} << 63) + 12345;  // not a power of two
  bool top_quarter = false;
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t x = rng.below(big);
    ASSERT_LT(x, big);
    top_quarter |= x >= (std::uint64_t{1} << 61) * 3;  // the top quarter of the range is reached
  }
  EXPECT_TRUE(top_quarter);
}

// Pearson's chi-square over n equiprobable classes.
double chi_square_below(Rng& rng, std::uint64_t n, int draws_per_class) {
  std::vector<int> counts(n, 0);
  const int total = static_cast<int>(n) * draws_per_class;
  for (int i = 0; i < total; ++i) {
    const std::uint64_t x = rng.below(n);
    EXPECT_LT(x, n);
    ++counts[x];
  }
  double chi2 = 0.0;
  for (int c : counts) chi2 += (c - draws_per_class) * static_cast<double>(c - draws_per_class) / draws_per_class;
  return chi2;
}

TEST(Rng, BelowIsRoughlyUniform) {
  // Chi-square with k - 1 degrees of freedom has mean k - 1 and SD sqrt(2 (k - 1)); the bounds
  // are far in the tail (p < 1e-6) but a biased generator (e.g. modulo by 3 of 2 bits, or an
  // off-by-one that never returns n - 1) exceeds them by orders of magnitude.
  Rng rng(4);
  EXPECT_LT(chi_square_below(rng, 10, 10'000), 9 + 8 * std::sqrt(18.0));
  EXPECT_LT(chi_square_below(rng, 3, 30'000), 2 + 12 * std::sqrt(4.0));
  EXPECT_LT(chi_square_below(rng, 100, 1'000), 99 + 7 * std::sqrt(198.0));
}

TEST(Rng, NormalHasMeanZeroAndUnitSd) {
  Rng rng(5);
  constexpr int kN = 100'000;
  const Moments m = moments(kN, [&] { return rng.normal(); });
  EXPECT_NEAR(m.mean, 0.0, 6 / std::sqrt(kN));        // SE 0.0032
  EXPECT_NEAR(m.sd, 1.0, 6 / std::sqrt(2.0 * kN));    // SE 0.0022
  EXPECT_NEAR(m.within_one_sd, 0.682689, 0.01);        // shape: P(|Z| < 1), SE 0.0015
}

TEST(Rng, NormalFloatHasMeanZeroAndUnitSd) {
  Rng rng(6);
  constexpr int kN = 100'000;
  const Moments m = moments(kN, [&] { return static_cast<double>(rng.normal_float()); });
  EXPECT_NEAR(m.mean, 0.0, 6 / std::sqrt(kN));
  EXPECT_NEAR(m.sd, 1.0, 6 / std::sqrt(2.0 * kN));
  EXPECT_NEAR(m.within_one_sd, 0.682689, 0.01);
}

TEST(Rng, NormalVariatesAreUncorrelatedPairs) {
  // The polar method returns both variates of a pair: they must not be correlated.
  Rng rng(7);
  constexpr int kN = 50'000;
  double sxy = 0.0;
  for (int i = 0; i < kN; ++i) {
    const double x = rng.normal();
    const double y = rng.normal();
    sxy += x * y;
  }
  EXPECT_NEAR(sxy / kN, 0.0, 6 / std::sqrt(kN));
}

TEST(Rng, GeometricHasMeanOneMinusPOverP) {
  for (const double p : {0.1, 0.5, 0.9}) {
    Rng rng(8);
    const auto inv = static_cast<float>(1.0 / std::log1p(-p));
    constexpr int kN = 100'000;
    double sum = 0.0;
    int zeros = 0;
    for (int i = 0; i < kN; ++i) {
      const std::uint32_t g = rng.geometric(inv);
      sum += g;
      zeros += g == 0;
    }
    const double mean = (1 - p) / p;
    const double sd = std::sqrt(1 - p) / p;
    EXPECT_NEAR(sum / kN, mean, 6 * sd / std::sqrt(kN)) << "p = " << p;
    // P(G = 0) = p.
    EXPECT_NEAR(static_cast<double>(zeros) / kN, p, 6 * std::sqrt(p * (1 - p) / kN)) << "p = " << p;
  }
}

TEST(Rng, StateRoundTripsMidStreamWithCachedSpares) {
  Rng rng(9);
  for (int i = 0; i < 17; ++i) rng();
  rng.normal();        // leaves a cached double spare
  rng.normal_float();  // leaves a cached float spare
  const Rng::State saved = rng.state();
  EXPECT_TRUE(saved.has_spare);
  EXPECT_TRUE(saved.has_spare_float);

  auto sequence = [](Rng& r) {
    std::vector<double> out;
    for (int i = 0; i < 20; ++i) {
      out.push_back(r.normal());
      out.push_back(static_cast<double>(r.normal_float()));
      out.push_back(r.uniform());
      out.push_back(static_cast<double>(r.below(1000)));
    }
    return out;
  };
  const std::vector<double> expected = sequence(rng);

  // The same object, and a fresh one with another seed, both resume identically.
  rng.set_state(saved);
  EXPECT_EQ(rng.state(), saved);
  EXPECT_EQ(sequence(rng), expected);
  Rng other(12345);
  other.set_state(saved);
  EXPECT_EQ(sequence(other), expected);

  // The first normal() after restoring is the cached spare, not a fresh draw.
  other.set_state(saved);
  EXPECT_EQ(other.normal(), saved.spare);
  EXPECT_EQ(other.normal_float(), saved.spare_float);
  // Without the spare the sequence would differ.
  Rng::State no_spare = saved;
  no_spare.has_spare = false;
  other.set_state(no_spare);
  EXPECT_NE(other.normal(), saved.spare);
}

TEST(Rng, StreamKeysAreDistinct) {
  const std::array keys = {StreamKey::kInitialPopulation, StreamKey::kVariation, StreamKey::kMetaFitness,
                           StreamKey::kMetaSampling,      StreamKey::kControl,   StreamKey::kTest,
                           StreamKey::kCentroids,         StreamKey::kAutoencoder};
  std::set<std::uint64_t> values;
  for (StreamKey k : keys) values.insert(key(k));
  EXPECT_EQ(values.size(), keys.size());
}

}  // namespace
}  // namespace qdmeta
