// AURORA's autoencoder: backpropagation against central finite differences, learning a known
// 2-D manifold embedded in 20-D, the input z-scoring, subsampling, early stopping and the
// determinism of training given its stream.
#include "qdmeta/featuremap/autoencoder.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "expect_input_error.hpp"

namespace qdmeta {
namespace {

Autoencoder make(AutoencoderParams p, std::uint64_t seed = 1) {
  Rng rng(seed);
  return Autoencoder(std::move(p), rng);
}

Autoencoder::Matrix normal_matrix(Index rows, Index cols, std::uint64_t seed) {
  Rng rng(seed);
  Autoencoder::Matrix x(rows, cols);
  for (Index i = 0; i < x.size(); ++i) x.data()[i] = rng.normal();
  return x;
}

// Points on a curved 2-D sheet in [0, 1]^20: every coordinate a smooth function of (s, t).
RowMatrix manifold(Index rows, std::uint64_t seed) {
  Rng rng(seed);
  RowMatrix x(rows, 20);
  for (Index i = 0; i < rows; ++i) {
    const double s = rng.uniform(), t = rng.uniform();
    for (Index j = 0; j < 20; ++j) {
      const double a = std::cos(0.7 * static_cast<double>(j)), b = std::sin(1.3 * static_cast<double>(j));
      x(i, j) = static_cast<Real>(0.5 + 0.2 * a * s + 0.2 * b * t + 0.1 * (a * b) * s * t);
    }
  }
  return x;
}

void expect_gradient_matches_central_differences(const AutoencoderParams& p, Index rows, Index stride) {
  Autoencoder ae = make(p, 5);
  // Random weights well away from the initial ones, so ReLUs are both on and off.
  Eigen::VectorXd w = ae.parameters();
  Rng rng(11);
  for (Index k = 0; k < w.size(); ++k) w[k] += 0.3 * rng.normal();
  ae.set_parameters(w);
  const Autoencoder::Matrix x = normal_matrix(rows, p.input_size, 3);

  Eigen::VectorXd gradient;
  const double loss = ae.loss_and_gradient(x, gradient);
  EXPECT_DOUBLE_EQ(loss, ae.loss(x));
  ASSERT_EQ(gradient.size(), ae.parameter_count());
  const double h = 1e-6;
  double worst = 0.0;
  for (Index k = 0; k < w.size(); k += stride) {
    Eigen::VectorXd plus = w, minus = w;
    plus[k] += h;
    minus[k] -= h;
    ae.set_parameters(plus);
    const double lp = ae.loss(x);
    ae.set_parameters(minus);
    const double lm = ae.loss(x);
    const double numeric = (lp - lm) / (2 * h);
    worst = std::max(worst, std::abs(numeric - gradient[k]) / std::max(1.0, std::abs(numeric)));
  }
  ae.set_parameters(w);
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(gradient.norm(), 1e-3);  // not trivially zero
}

TEST(Autoencoder, GradientMatchesCentralDifferencesOnASmallNetwork) {
  AutoencoderParams p;
  p.input_size = 6;
  p.hidden = {5, 4};
  p.latent_size = 2;
  expect_gradient_matches_central_differences(p, 9, 1);
}

TEST(Autoencoder, GradientMatchesCentralDifferencesOnThePapersNetwork) {
  AutoencoderParams p;  // 20 -> 32 -> 8 -> 2 -> 8 -> 32 -> 20
  expect_gradient_matches_central_differences(p, 16, 7);
}

TEST(Autoencoder, ParameterCountFollowsTheLayerWidths) {
  const Autoencoder ae = make({});
  // 20*32+32 + 32*8+8 + 8*2+2 + 2*8+8 + 8*32+32 + 32*20+20
  EXPECT_EQ(ae.parameter_count(), 672 + 264 + 18 + 24 + 288 + 660);
  // PyTorch's initialisation: every first-layer weight within 1/sqrt(20).
  EXPECT_LE(ae.parameters().head(672).cwiseAbs().maxCoeff(), 1.0 / std::sqrt(20.0));
}

TEST(Autoencoder, LearnsATwoDimensionalManifoldWellBelowItsVariance) {
  AutoencoderParams p;
  p.learning_rate = 0.03;
  p.max_epochs = 400;
  p.stopping_window = 1'000'000;  // no early stopping: measure the fit itself
  Autoencoder ae = make(p);
  const RowMatrix x = manifold(200, 2);
  Rng rng(3);
  const TrainingReport r = ae.train(x, rng);
  EXPECT_EQ(r.epochs, 400);
  // z-scored inputs have variance about 1 per entry; the initial loss is about that.
  EXPECT_GT(r.initial_training_loss, 0.5);
  const double final_loss = ae.loss(ae.normalise(x.data(), x.rows()));
  EXPECT_LT(final_loss, 0.005) << "initial " << r.initial_training_loss;  // 0.00017 when written
  // On fresh points of the same sheet, too.
  const RowMatrix fresh = manifold(200, 99);
  EXPECT_LT(ae.loss(ae.normalise(fresh.data(), fresh.rows())), 0.01);
}

TEST(Autoencoder, ThePapersSettingsLowerTheLoss) {
  Autoencoder ae = make({});
  const RowMatrix x = manifold(2000, 4);  // above 500 rows: validation split in force
  Rng rng(5);
  const TrainingReport r = ae.train(x, rng);
  EXPECT_LE(r.epochs, 100);
  EXPECT_LT(r.final_training_loss, r.initial_training_loss);
  EXPECT_LT(ae.loss(ae.normalise(x.data(), x.rows())), r.initial_training_loss);
}

TEST(Autoencoder, InputsAreZScoredOverTheTrainingSetWithEpsilon) {
  AutoencoderParams p;
  p.input_size = 3;
  p.max_epochs = 1;
  Autoencoder ae = make(p);
  RowMatrix x(4, 3);
  x << 0, 1, 5,  //
      1, 1, 5,   //
      2, 1, 5,   //
      3, 1, 9;
  Rng rng(1);
  ae.train(x, rng);
  EXPECT_DOUBLE_EQ(ae.input_mean()[0], 1.5);
  EXPECT_DOUBLE_EQ(ae.input_mean()[1], 1.0);
  EXPECT_DOUBLE_EQ(ae.input_mean()[2], 6.0);
  EXPECT_DOUBLE_EQ(ae.input_scale()[0], std::sqrt(1.25) + 1e-3);  // population SD
  EXPECT_DOUBLE_EQ(ae.input_scale()[1], 1e-3);                    // constant input: epsilon alone
  EXPECT_DOUBLE_EQ(ae.input_scale()[2], std::sqrt(3.0) + 1e-3);
  const Autoencoder::Matrix z = ae.normalise(x.data(), 4);
  EXPECT_NEAR(z(0, 0), -1.5 / (std::sqrt(1.25) + 1e-3), 1e-12);
  EXPECT_EQ(z(2, 1), 0.0);
}

TEST(Autoencoder, WithoutASplitTheValidationLossIsTheLossOnAllRows) {
  AutoencoderParams p;
  p.max_epochs = 7;
  Autoencoder ae = make(p);
  const RowMatrix x = manifold(500, 8);  // not above split_min_rows
  Rng rng(2);
  const TrainingReport r = ae.train(x, rng);
  EXPECT_EQ(r.rows, 500);
  EXPECT_EQ(r.final_validation_loss, ae.loss(ae.normalise(x.data(), x.rows())));
}

TEST(Autoencoder, LargeTrainingSetsAreSubsampled) {
  AutoencoderParams p;
  p.max_training_rows = 300;
  p.max_epochs = 2;
  Autoencoder ae = make(p);
  const RowMatrix x = manifold(1000, 8);
  Rng rng(2);
  EXPECT_EQ(ae.train(x, rng).rows, 300);
}

TEST(Autoencoder, StopsEarlyWhenTheValidationLossRisesAfterProgress) {
  // A step size far too large: the loss first drops, then the validation losses climb.
  AutoencoderParams p;
  p.learning_rate = 0.3;
  p.max_epochs = 2000;
  Autoencoder ae = make(p);
  const RowMatrix x = manifold(800, 6);
  Rng rng(4);
  const TrainingReport r = ae.train(x, rng);
  EXPECT_TRUE(r.stopped_early);
  EXPECT_LT(r.epochs, 2000);
  EXPECT_GE(r.epochs, 5);
  EXPECT_LT(r.final_training_loss, r.initial_training_loss);
}

TEST(Autoencoder, TrainingIsDeterministicGivenItsStream) {
  const RowMatrix x = manifold(700, 1);
  Autoencoder a = make({}, 9), b = make({}, 9), c = make({}, 10);
  Rng ra(3), rb(3), rc(3);
  a.train(x, ra);
  b.train(x, rb);
  c.train(x, rc);
  EXPECT_TRUE(a.parameters() == b.parameters());  // bit-identical
  EXPECT_FALSE(a.parameters() == c.parameters());
  const Autoencoder::Matrix codes = a.encode(x.data(), x.rows());
  EXPECT_EQ(codes.rows(), 700);
  EXPECT_EQ(codes.cols(), 2);
  EXPECT_TRUE(codes == b.encode(x.data(), x.rows()));
}

TEST(Autoencoder, EncodingInBlocksOfWholeRowPanelsGivesTheBitsOfOneCall) {
  // Blocks that start at multiples of 48 rows, the last one taking the rest: what AURORA's
  // parallel encoding does. Row counts around the product's panel sizes and a rebuild's size.
  Autoencoder a = make({}, 4);
  Rng rng(8);
  a.train(manifold(600, 2), rng);
  Autoencoder::Workspace workspace;
  for (const Index rows : {1, 2, 3, 5, 11, 12, 13, 47, 48, 49, 95, 97, 143, 400, 401, 1001, 2017, 10055}) {
    const RowMatrix x = manifold(rows, static_cast<std::uint64_t>(rows));
    const Autoencoder::Matrix whole = a.encode(x.data(), rows);
    for (const Index block : {48, 96, 960}) {
      Autoencoder::Matrix pieces(rows, 2);
      const Index blocks = std::max<Index>(1, rows / block);
      for (Index b = 0; b < blocks; ++b) {
        const Index first = b * block, n = b + 1 == blocks ? rows - first : block;
        a.encode(x.data() + first * x.cols(), n, pieces.middleRows(first, n), workspace);
      }
      EXPECT_TRUE(pieces == whole) << rows << " rows in blocks of " << block;
    }
  }
}

TEST(Autoencoder, BadParametersNameTheKey) {
  AutoencoderParams p;
  p.latent_size = 0;
  EXPECT_INPUT_ERROR(make(p), "aurora.latent_size = 0 is out of range: must be in [1, 1000]");
  p = {};
  p.hidden = {};
  EXPECT_INPUT_ERROR(make(p), "aurora.hidden is empty: give at least one hidden layer width");
}

}  // namespace
}  // namespace qdmeta
