// Tests of src/qdmeta/emitters/iso_line_emitter.{hpp,cpp}: the draws of one row written out, rows
// on the lines between elites when iso_sigma = 0, the batch's mean and covariance against the
// operator's closed form, clamping and the settings refused.
#include "qdmeta/emitters/iso_line_emitter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/core/fused.hpp"

namespace qdmeta {
namespace {

// Three elites of two genes, not on one line; the picker draws one uniformly, as elite_picker does.
const std::vector<std::vector<double>> kElites{{0.0, 0.0}, {4.0, 0.0}, {0.0, 2.0}};

bool pick_elite(Rng& rng, std::vector<double>& genes) {
  genes = kElites[rng.below(kElites.size())];
  return true;
}

IsoLineEmitterParams iso_line_params(double iso, double line, int batch) {
  IsoLineEmitterParams p;
  p.x0 = {0.5, 0.5};
  p.iso_sigma = iso;
  p.line_sigma = line;
  p.batch_size = batch;
  return p;
}

TEST(IsoLineEmitter, ARowIsTheFirstEliteAlongTheSecondPlusIsotropicNoise) {
  IsoLineEmitter e(iso_line_params(0.1, 0.3, 4), pick_elite);
  Rng rng(7), expected(7);
  const RowMatrix batch = e.ask(rng);
  for (Index r = 0; r < 4; ++r) {
    const std::vector<double> xi = kElites[expected.below(3)], xj = kElites[expected.below(3)];
    const double line = 0.3 * expected.normal();
    for (Index g = 0; g < 2; ++g) {
      const auto k = static_cast<std::size_t>(g);
      const double gene = fused(0.1, expected.normal(), fused(line, xj[k] - xi[k], xi[k]));
      EXPECT_EQ(batch(r, g), static_cast<Real>(gene)) << "row " << r << " gene " << g;
    }
  }
}

TEST(IsoLineEmitter, WithoutIsotropicNoiseEveryRowLiesOnALineBetweenTwoElites) {
  IsoLineEmitter e(iso_line_params(0.0, 1.0, 500), pick_elite);
  Rng rng(8);
  const RowMatrix batch = e.ask(rng);
  int off_the_axes = 0;
  for (Index r = 0; r < batch.rows(); ++r) {
    const double x = batch(r, 0), y = batch(r, 1);
    // The lines through the elites: y = 0, x = 0 and x / 4 + y / 2 = 1 (float rows: 1e-5).
    const bool on_a_line = std::abs(y) < 1e-5 || std::abs(x) < 1e-5 || std::abs(x / 4 + y / 2 - 1) < 1e-5;
    EXPECT_TRUE(on_a_line) << "row " << r << ": (" << x << ", " << y << ")";
    off_the_axes += std::abs(y) > 1e-3 && std::abs(x) > 1e-3;
  }
  EXPECT_GT(off_the_axes, 50);  // the hypotenuse is drawn too (2 of 9 pairs)
}

TEST(IsoLineEmitter, MeanAndCovarianceMatchTheClosedForm) {
  // x_i, x_j independent uniform elites of mean m and covariance S: E[row] = m and
  // Cov[row] = (1 + 2 line^2) S + iso^2 I, the line's normal being shared by the genes.
  const double iso = 0.5, line = 1.0;
  const int n = 200000;
  IsoLineEmitter e(iso_line_params(iso, line, n), pick_elite);
  Rng rng(9);
  const RowMatrix batch = e.ask(rng);
  const double m[2] = {4.0 / 3, 2.0 / 3};
  double s[2][2] = {};
  for (const auto& x : kElites)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) s[a][b] += (x[a] - m[a]) * (x[b] - m[b]) / 3.0;
  double mean[2] = {}, cov[2][2] = {};
  for (Index r = 0; r < n; ++r)
    for (int a = 0; a < 2; ++a) mean[a] += batch(r, a) / double{n};
  for (Index r = 0; r < n; ++r)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) cov[a][b] += (batch(r, a) - mean[a]) * (batch(r, b) - mean[b]) / double{n};
  for (int a = 0; a < 2; ++a) {
    // Standard errors at n = 200000: about 0.005 for the means, 0.05 for the covariances;
    // a line normal drawn per gene would make cov[0][1] = S01 = -0.89, not 3 S01 = -2.67.
    EXPECT_NEAR(mean[a], m[a], 0.03) << a;
    for (int b = 0; b < 2; ++b) {
      const double closed_form = (1 + 2 * line * line) * s[a][b] + (a == b ? iso * iso : 0.0);
      EXPECT_NEAR(cov[a][b], closed_form, 0.25) << a << b;
    }
  }
}

TEST(IsoLineEmitter, StartsFromX0AndClampsToTheBounds) {
  auto p = iso_line_params(0.2, 0.2, 300);
  p.lower_bound = 0.4;
  p.upper_bound = 0.6;
  IsoLineEmitter e(p, [](Rng&, std::vector<double>&) { return false; });
  Rng rng(10), expected(10);
  const RowMatrix batch = e.ask(rng);
  expected.normal();  // the line's normal, on a zero direction
  EXPECT_EQ(batch(0, 0), static_cast<Real>(std::clamp(fused(0.2, expected.normal(), 0.5), 0.4, 0.6)));
  EXPECT_EQ(batch.minCoeff(), 0.4f);
  EXPECT_EQ(batch.maxCoeff(), 0.6f);
}

TEST(IsoLineEmitter, RefusesBadSettingsNamingTheKey) {
  auto p = iso_line_params(-0.1, 0.2, 1);
  EXPECT_INPUT_ERROR(p.validate(), "emitters.iso_sigma = -0.1 is out of range: must be a number >= 0");
  p = iso_line_params(0.1, NAN, 1);
  EXPECT_INPUT_ERROR(p.validate(), "emitters.line_sigma = nan is out of range: must be a number >= 0");
  p = iso_line_params(0.1, 0.2, 0);
  EXPECT_INPUT_ERROR(IsoLineEmitter(p, {}), "emitters.batch_size = 0 is out of range: must be in [1, 1000000]");
  p = iso_line_params(0.1, 0.2, 1);
  p.x0.clear();
  EXPECT_INPUT_ERROR(p.validate(), "IsoLineEmitterParams.x0 is empty: give the first parent, one value per gene");
  IsoLineEmitter e(iso_line_params(0.1, 0.2, 1), {});
  Rng rng(1);
  e.ask(rng);
  EXPECT_INPUT_ERROR(e.ask(rng), "IsoLineEmitter::ask: called twice without tell; tell the last batch's outcomes first");
}

}  // namespace
}  // namespace qdmeta
