// Tests of the iso+line operator (Mutation::apply_iso_line, Vassiliades & Mouret 2018):
// offspring = clamp(x_i + iso_sigma z + line_sigma w (x_j - x_i), 0, 1), z ~ N(0, I), w ~ N(0, 1),
// against values computed from its definition, and its moments along and across the line.
#include <gtest/gtest.h>

#include "expect_input_error.hpp"
#include "mutation_params.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/mutation.hpp"

namespace qdmeta {
namespace {

TEST(IsoLine, DefaultsArePyribsAndNamed) {
  const MutationParams p;
  EXPECT_DOUBLE_EQ(p.iso_sigma, 0.01);
  EXPECT_DOUBLE_EQ(p.line_sigma, 0.2);
  EXPECT_EQ(enum_from_string(kMutationKindNames, "mutation.kind", "iso-line"), MutationKind::kIsoLine);
  EXPECT_TRUE(Mutation(iso_line()).needs_two_parents());
  EXPECT_FALSE(Mutation(MutationParams{}).needs_two_parents());
}

// Each gene from the formula, with the draws taken from a copy of the generator in the
// documented order (w, then z_0 .. z_{n-1}); the sum in double.
TEST(IsoLine, OffspringFollowTheDefinition) {
  const std::vector<Real> xi = {0.1f, 0.5f, 0.9f, 0.3f, 0.0f, 1.0f, 0.45f};
  const std::vector<Real> xj = {0.2f, 0.4f, 0.1f, 0.3f, 1.0f, 0.0f, 0.95f};
  const auto n = static_cast<Index>(xi.size());
  for (const auto& [iso, line] : {std::pair{0.01, 0.2}, std::pair{0.3, 1.5}, std::pair{0.0, 0.7}}) {
    const Mutation m(iso_line(iso, line));
    for (std::uint64_t seed = 1; seed <= 50; ++seed) {
      Rng rng(seed), draws(seed);
      std::vector<Real> child = xi;
      m.apply_iso_line(child.data(), xj.data(), n, rng);
      const double w = draws.normal_float();
      for (Index k = 0; k < n; ++k) {
        const auto u = static_cast<std::size_t>(k);
        const double z = draws.normal_float();
        const double expected = std::clamp(xi[u] + iso * z + line * w * (double{xj[u]} - xi[u]), 0.0, 1.0);
        EXPECT_NEAR(child[u], expected, 1e-6) << "iso " << iso << " line " << line << " seed " << seed << " gene " << k;
      }
      EXPECT_EQ(rng.state(), draws.state()) << "one line draw and one iso draw per gene";
    }
  }
}

// x_i = 0.5 everywhere, x_j = x_i + 0.25 on genes 0 and 1: along the line each of those genes
// moves by iso z + line w 0.25 (variance iso^2 + line^2 / 16), both with the same w (covariance
// line^2 / 16); across it the others move by iso z alone. 200,000 offspring: a sample variance
// has a standard error of 0.3%, so the 2% tolerance (6 standard errors) fails for a sigma 2%
// off (variance about 4% off) and for a line draw per gene (covariance 0).
TEST(IsoLine, MomentsAlongAndAcrossTheLine) {
  constexpr Index kN = 6;
  constexpr int kDraws = 200'000;
  const double iso = 0.01, line = 0.2, d = 0.25;
  const std::vector<Real> xi(kN, 0.5f);
  std::vector<Real> xj = xi;
  xj[0] = xj[1] = 0.75f;
  const Mutation m(iso_line(iso, line));
  Rng rng(2018);
  std::vector<double> sum(kN, 0.0), sum2(kN, 0.0);
  double cross = 0.0;
  for (int t = 0; t < kDraws; ++t) {
    std::vector<Real> child = xi;
    m.apply_iso_line(child.data(), xj.data(), kN, rng);
    for (Index k = 0; k < kN; ++k) {
      const double v = child[static_cast<std::size_t>(k)] - 0.5;
      sum[static_cast<std::size_t>(k)] += v;
      sum2[static_cast<std::size_t>(k)] += v * v;
    }
    cross += (child[0] - 0.5) * (child[1] - 0.5);
  }
  const double along = iso * iso + line * line * d * d, across = iso * iso;
  for (Index k = 0; k < kN; ++k) {
    const auto u = static_cast<std::size_t>(k);
    const double mean = sum[u] / kDraws, var = sum2[u] / kDraws - mean * mean;
    const double expected = k < 2 ? along : across;
    EXPECT_NEAR(mean, 0.0, 5 * std::sqrt(expected / kDraws)) << "gene " << k;
    EXPECT_NEAR(var / expected, 1.0, 0.02) << "gene " << k;
  }
  EXPECT_NEAR(cross / kDraws / (line * line * d * d), 1.0, 0.02);
}

TEST(IsoLine, ClampsToTheUnitIntervalAndZeroSigmasCopy) {
  constexpr Index kN = 1000;
  const std::vector<Real> xi(kN, 0.0f), xj(kN, 1.0f);
  std::vector<Real> child = xi;
  Rng rng(5);
  Index at_zero = 0, at_one = 0;
  for (int t = 0; t < 200; ++t) {
    child = xi;
    Mutation(iso_line(0.5, 2.0)).apply_iso_line(child.data(), xj.data(), kN, rng);
    for (Real g : child) {
      ASSERT_GE(g, 0.0f);
      ASSERT_LE(g, 1.0f);
      at_zero += g == 0.0f;
      at_one += g == 1.0f;
    }
  }
  EXPECT_GT(at_zero, 0);
  EXPECT_GT(at_one, 0);

  std::vector<Real> a = {0.2f, 0.7f}, b = {0.9f, 0.1f};
  Mutation(iso_line(0.0, 0.0)).apply_iso_line(a.data(), b.data(), 2, rng);
  EXPECT_EQ(a, (std::vector<Real>{0.2f, 0.7f}));
}

TEST(IsoLine, ValidatesItsSigmasAndRefusesOneParent) {
  EXPECT_NE(message_of(iso_line(-0.1, 0.2)).find("mutation.iso_sigma = -0.1"), std::string::npos);
  EXPECT_NE(message_of(iso_line(0.01, -1.0)).find("mutation.line_sigma = -1"), std::string::npos);
  EXPECT_NE(message_of(iso_line(std::nan(""), 0.2)).find("mutation.iso_sigma"), std::string::npos);
  // The Gaussian sigma and the grid step do not concern it.
  MutationParams p = iso_line();
  p.sigma = 0.0;
  p.step = 0.3;
  EXPECT_NO_THROW(p.validate());
  std::vector<Real> genes(4, 0.5f);
  Rng rng(1);
  EXPECT_THROW(Mutation(iso_line()).apply(genes.data(), 4, rng), Error);
}

}  // namespace
}  // namespace qdmeta
