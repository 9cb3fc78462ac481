// Tests of src/qdmeta/core/mutation.{hpp,cpp}: per-gene rate, Gaussian step size and clamping,
// the discrete-step and uniform-resample grids, and MutationParams::validate messages.
#include "qdmeta/core/mutation.hpp"

#include <gtest/gtest.h>

#include "expect_input_error.hpp"
#include "mutation_params.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "qdmeta/core/copy_row.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/fused.hpp"

namespace qdmeta {
namespace {

MutationParams grid(MutationKind kind, double rate, double step = 0.025) {
  MutationParams p;
  p.kind = kind;
  p.rate = rate;
  p.step = step;
  return p;
}

// Genes on the grid {k / 40}, as float.
Real on_grid(long k) { return static_cast<Real>(static_cast<double>(k) / 40.0); }
bool is_on_grid(Real g) {
  const double k = std::round(static_cast<double>(g) * 40.0);
  return k >= 0 && k <= 40 && g == on_grid(static_cast<long>(k));
}

TEST(Mutation, DefaultParamsAreValidAndMatchThePaper) {
  const MutationParams p;
  EXPECT_NO_THROW(p.validate());
  EXPECT_EQ(p.kind, MutationKind::kGaussian);
  EXPECT_DOUBLE_EQ(p.rate, 0.10);
  EXPECT_DOUBLE_EQ(p.sigma, 0.05);
  EXPECT_DOUBLE_EQ(p.step, 0.025);
}

TEST(Mutation, GaussianRateAndSigma) {
  constexpr Index kN = 100'000;
  std::vector<Real> genes(kN, 0.5f);
  Rng rng(11);
  Mutation(gaussian(0.1)).apply(genes.data(), kN, rng);
  Index changed = 0;
  double sum = 0.0, sum2 = 0.0;
  for (Real g : genes) {
    ASSERT_GE(g, 0.0f);
    ASSERT_LE(g, 1.0f);
    if (g == 0.5f) continue;
    ++changed;
    const double d = static_cast<double>(g) - 0.5;
    sum += d;
    sum2 += d * d;
  }
  // Binomial(1e5, 0.1): mean 10,000, SD 94.9; allow 6 SD.
  EXPECT_NEAR(static_cast<double>(changed), 10'000.0, 6 * std::sqrt(kN * 0.1 * 0.9));
  const double mean = sum / static_cast<double>(changed);
  const double sd = std::sqrt(sum2 / static_cast<double>(changed) - mean * mean);
  EXPECT_NEAR(mean, 0.0, 6 * 0.05 / std::sqrt(10'000.0));  // SE 0.0005
  EXPECT_NEAR(sd, 0.05, 0.003);                            // SE of the SD 0.00035
}

TEST(Mutation, GaussianRateIsUniformAcrossTheBlock) {
  // The geometric skipping must not favour the start or the end of a block: count mutations in
  // ten equal slices of many small blocks.
  constexpr Index kBlock = 400;
  std::vector<int> per_slice(10, 0);
  Rng rng(12);
  const Mutation m(gaussian(0.1));
  for (int rep = 0; rep < 500; ++rep) {
    std::vector<Real> genes(kBlock, 0.5f);
    m.apply(genes.data(), kBlock, rng);
    for (Index i = 0; i < kBlock; ++i) per_slice[static_cast<std::size_t>(i * 10 / kBlock)] += genes[i] != 0.5f;
  }
  // Each slice: Binomial(500 x 40, 0.1), mean 2000, SD 42.4.
  for (int c : per_slice) EXPECT_NEAR(c, 2000, 6 * 42.4);
}

TEST(Mutation, GaussianClampsToUnitInterval) {
  constexpr Index kN = 20'000;
  std::vector<Real> genes(kN);
  for (Index i = 0; i < kN; ++i) genes[static_cast<std::size_t>(i)] = (i % 2 == 0) ? 0.0f : 1.0f;
  Rng rng(13);
  Mutation(gaussian(1.0, 0.2)).apply(genes.data(), kN, rng);
  int at_zero = 0, at_one = 0, moved_from_zero = 0, moved_from_one = 0;
  for (Index i = 0; i < kN; ++i) {
    const Real g = genes[static_cast<std::size_t>(i)];
    ASSERT_GE(g, 0.0f);
    ASSERT_LE(g, 1.0f);
    if (i % 2 == 0) (g == 0.0f ? at_zero : moved_from_zero)++;
    else (g == 1.0f ? at_one : moved_from_one)++;
  }
  // Half the moves push out of range and are clamped back onto the end.
  EXPECT_NEAR(at_zero, kN / 4, 6 * std::sqrt(kN / 2 * 0.25));
  EXPECT_NEAR(at_one, kN / 4, 6 * std::sqrt(kN / 2 * 0.25));
  EXPECT_GT(moved_from_zero, 0);
  EXPECT_GT(moved_from_one, 0);
}

TEST(Mutation, RateZeroChangesNothing) {
  for (MutationKind kind : {MutationKind::kGaussian, MutationKind::kDiscreteStep, MutationKind::kUniformResample}) {
    RowMatrix genes(50, 20);
    Rng init(14);
    for (Index k = 0; k < genes.size(); ++k) genes.data()[k] = on_grid(static_cast<long>(init.below(41)));
    const RowMatrix before = genes;
    Rng rng(15);
    const Rng::State rng_before = rng.state();
    MutationParams p = grid(kind, 0.0);
    Mutation(p).apply(genes, rng);
    EXPECT_EQ(genes, before);
    EXPECT_EQ(rng.state(), rng_before);  // not even a draw
  }
}

TEST(Mutation, RateOneChangesEveryGene) {
  constexpr Index kN = 10'000;
  std::vector<Real> genes(kN, 0.5f);
  Rng rng(16);
  Mutation(gaussian(1.0)).apply(genes.data(), kN, rng);
  for (Real g : genes) ASSERT_NE(g, 0.5f);

  // Discrete steps from an inner grid point always move.
  std::vector<Real> steps(kN, on_grid(20));
  Mutation(grid(MutationKind::kDiscreteStep, 1.0)).apply(steps.data(), kN, rng);
  for (Real g : steps) ASSERT_TRUE(g == on_grid(19) || g == on_grid(21)) << g;
}

TEST(Mutation, MatrixApplyEqualsFlatApply) {
  RowMatrix a(40, 20);
  a.setConstant(0.5f);
  std::vector<Real> b(800, 0.5f);
  Rng ra(17), rb(17);
  const Mutation m(gaussian(0.3));
  m.apply(a, ra);
  m.apply(b.data(), static_cast<Index>(b.size()), rb);
  for (Index k = 0; k < a.size(); ++k) ASSERT_EQ(a.data()[k], b[static_cast<std::size_t>(k)]) << k;
  EXPECT_EQ(ra.state(), rb.state());
}

TEST(Mutation, SameSeedSameResult) {
  std::vector<Real> a(5000, 0.25f), b(5000, 0.25f);
  Rng ra(18), rb(18);
  const Mutation m(gaussian(0.1));
  m.apply(a.data(), 5000, ra);
  m.apply(b.data(), 5000, rb);
  EXPECT_EQ(a, b);
}

TEST(Mutation, DiscreteStepMovesExactlyOneStepOnTheGrid) {
  constexpr Index kN = 41 * 1000;
  std::vector<Real> genes(kN);
  for (Index i = 0; i < kN; ++i) genes[static_cast<std::size_t>(i)] = on_grid(i % 41);
  const std::vector<Real> before = genes;
  Rng rng(19);
  Mutation(grid(MutationKind::kDiscreteStep, 0.125)).apply(genes.data(), kN, rng);
  int changed = 0, up = 0, down = 0;
  for (Index i = 0; i < kN; ++i) {
    const Real g = genes[static_cast<std::size_t>(i)];
    const Real old = before[static_cast<std::size_t>(i)];
    ASSERT_TRUE(is_on_grid(g)) << g;
    if (g == old) continue;
    ++changed;
    const long k_old = i % 41;
    ASSERT_TRUE(g == on_grid(k_old - 1) || g == on_grid(k_old + 1)) << old << " -> " << g;
    ASSERT_NEAR(std::abs(static_cast<double>(g) - static_cast<double>(old)), 0.025, 1e-6);
    (g > old ? up : down)++;
  }
  // About rate x (1 - 1/41) of the genes change (the ends stay put half the time).
  const double p = 0.125 * (1.0 - 1.0 / 41);
  EXPECT_NEAR(changed, kN * p, 6 * std::sqrt(kN * p * (1 - p)));
  EXPECT_NEAR(up, down, 6 * std::sqrt(static_cast<double>(changed)));
}

TEST(Mutation, DiscreteStepClampsAtTheEnds) {
  constexpr Index kN = 2000;
  std::vector<Real> genes(kN);
  for (Index i = 0; i < kN; ++i) genes[static_cast<std::size_t>(i)] = (i % 2 == 0) ? 0.0f : 1.0f;
  Rng rng(20);
  Mutation(grid(MutationKind::kDiscreteStep, 1.0)).apply(genes.data(), kN, rng);
  int stayed = 0;
  for (Index i = 0; i < kN; ++i) {
    const Real g = genes[static_cast<std::size_t>(i)];
    const bool ok = (i % 2 == 0) ? (g == 0.0f || g == on_grid(1)) : (g == 1.0f || g == on_grid(39));
    ASSERT_TRUE(ok) << "gene " << i << " -> " << g;
    stayed += g == ((i % 2 == 0) ? 0.0f : 1.0f);
  }
  EXPECT_NEAR(stayed, kN / 2, 6 * std::sqrt(kN * 0.25));
}

TEST(Mutation, UniformResampleStaysOnTheGridAndCoversIt) {
  constexpr Index kN = 41 * 500;
  std::vector<Real> genes(kN, 0.5f);
  Rng rng(21);
  Mutation(grid(MutationKind::kUniformResample, 1.0)).apply(genes.data(), kN, rng);
  std::vector<int> counts(41, 0);
  for (Real g : genes) {
    ASSERT_TRUE(is_on_grid(g)) << g;
    ++counts[static_cast<std::size_t>(std::lround(static_cast<double>(g) * 40))];
  }
  // Each of the 41 values about 500 times (SD 22): both ends included.
  for (int c : counts) EXPECT_NEAR(c, 500, 6 * 22.1);
}

TEST(Mutation, UniformResampleWithCoarseStep) {
  constexpr Index kN = 3000;
  std::vector<Real> genes(kN, 0.3f);
  Rng rng(22);
  Mutation(grid(MutationKind::kUniformResample, 1.0, 0.25)).apply(genes.data(), kN, rng);
  for (Real g : genes) ASSERT_TRUE(g == 0.0f || g == 0.25f || g == 0.5f || g == 0.75f || g == 1.0f) << g;
}

TEST(Mutation, ValidateNamesFieldAndValue) {
  const std::string rate = message_of(gaussian(1.5));
  EXPECT_NE(rate.find("mutation.rate"), std::string::npos) << rate;
  EXPECT_NE(rate.find("1.5"), std::string::npos) << rate;
  EXPECT_NE(message_of(gaussian(-0.1)).find("mutation.rate"), std::string::npos);

  const std::string sigma = message_of(gaussian(0.1, 0.0));
  EXPECT_NE(sigma.find("mutation.sigma = 0"), std::string::npos) << sigma;
  EXPECT_NE(message_of(gaussian(0.1, -1.0)).find("mutation.sigma = -1"), std::string::npos);
  EXPECT_NE(message_of(gaussian(0.1, std::nan(""))).find("mutation.sigma"), std::string::npos);

  const std::string step = message_of(grid(MutationKind::kDiscreteStep, 0.1, 0.3));
  EXPECT_NE(step.find("mutation.step = 0.3"), std::string::npos) << step;
  EXPECT_NE(step.find("divide 1"), std::string::npos) << step;
  EXPECT_NE(message_of(grid(MutationKind::kUniformResample, 0.1, 0.3)).find("mutation.step = 0.3"), std::string::npos);
  EXPECT_NE(message_of(grid(MutationKind::kDiscreteStep, 0.1, 0.0)).find("mutation.step = 0"), std::string::npos);
  EXPECT_NE(message_of(grid(MutationKind::kDiscreteStep, 0.1, 1.5)).find("mutation.step = 1.5"), std::string::npos);

  // Steps that divide 1 are valid, including ones not exact in binary.
  for (double s : {0.025, 0.1, 0.2, 0.5, 1.0, 1.0 / 3}) EXPECT_NO_THROW(grid(MutationKind::kDiscreteStep, 0.1, s).validate()) << s;
  // The step is not checked for the Gaussian kind, nor sigma for the grid kinds.
  MutationParams p = gaussian(0.1);
  p.step = 0.3;
  EXPECT_NO_THROW(p.validate());
  p = grid(MutationKind::kDiscreteStep, 0.1);
  p.sigma = 0.0;
  EXPECT_NO_THROW(p.validate());
}

TEST(Mutation, ConstructorValidates) {
  EXPECT_THROW(Mutation{gaussian(1.5)}, InputError);
  EXPECT_THROW(Mutation{grid(MutationKind::kDiscreteStep, 0.1, 0.3)}, InputError);
}

TEST(Mutation, KindNamesRoundTrip) {
  for (const auto& [kind, name] : kMutationKindNames) {
    EXPECT_EQ(enum_to_string(kMutationKindNames, kind), name);
    EXPECT_EQ(enum_from_string(kMutationKindNames, "mutation.kind", name), kind);
  }
  try {
    enum_from_string(kMutationKindNames, "mutation.kind", "gauss");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "mutation.kind = \"gauss\" is not a valid choice: use one of \"gaussian\", \"discrete-step\", "
                 "\"uniform-resample\", \"iso-line\"");
  }
}

}  // namespace
}  // namespace qdmeta

// The Gaussian fast path (apply_gaussian) against the definition written out gene by gene: the
// same geometric skips and polar normals from the same generator, so the same bits and the same
// generator state after (the spare normal included).
TEST(Mutation, GaussianFastPathGivesTheBitsOfThePerGeneDefinition) {
  qdmeta::MutationParams p;  // gaussian, rate 0.10, sigma 0.05
  const qdmeta::Mutation mutation(p);
  const auto inv = static_cast<float>(1.0 / std::log1p(-p.rate));
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    qdmeta::Rng init(seed);
    qdmeta::RowMatrix fast(400, 20);
    for (Eigen::Index k = 0; k < fast.size(); ++k) fast.data()[k] = static_cast<float>(init.uniform());
    qdmeta::RowMatrix slow = fast;
    qdmeta::Rng a(seed + 100), b(seed + 100);
    mutation.apply(fast, a);
    std::uint64_t pos = b.geometric(inv);
    const auto n = static_cast<std::uint64_t>(slow.size());
    while (pos < n) {
      const float g = qdmeta::fused(static_cast<float>(p.sigma), b.normal_float(), slow.data()[pos]);
      slow.data()[pos] = std::clamp(g, 0.0f, 1.0f);
      pos += 1 + b.geometric(inv);
    }
    EXPECT_EQ(0, std::memcmp(fast.data(), slow.data(), sizeof(float) * static_cast<std::size_t>(n)));
    EXPECT_EQ(a.state(), b.state());
  }
}

// copy_row's fixed-size moves cover every length exactly: nothing before or after the row touched.
TEST(CopyRow, CopiesEveryLengthAndNothingElse) {
  for (qdmeta::Index n = 0; n <= 70; ++n) {
    std::vector<float> src(static_cast<std::size_t>(n)), dst(static_cast<std::size_t>(n) + 2, -1.0f);
    for (qdmeta::Index k = 0; k < n; ++k) src[static_cast<std::size_t>(k)] = static_cast<float>(k + 1);
    qdmeta::copy_row(src.data(), n, dst.data() + 1);
    EXPECT_EQ(dst.front(), -1.0f) << n;
    EXPECT_EQ(dst.back(), -1.0f) << n;
    for (qdmeta::Index k = 0; k < n; ++k) EXPECT_EQ(dst[static_cast<std::size_t>(k) + 1], src[static_cast<std::size_t>(k)]) << n;
  }
}
