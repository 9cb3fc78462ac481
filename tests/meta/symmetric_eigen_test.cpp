#include "qdmeta/meta/symmetric_eigen.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>

#include "expect_input_error.hpp"
#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

// A = Q diag(values) Q^T with Q a Householder reflection I - 2 u u^T / u^T u: a known spectrum
// and known eigenvectors (the columns of Q).
Eigen::MatrixXd with_spectrum(const Eigen::VectorXd& values, const Eigen::MatrixXd& q) {
  return q * values.asDiagonal() * q.transpose();
}

Eigen::MatrixXd householder(Eigen::Index n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd u(n);
  for (Eigen::Index i = 0; i < n; ++i) u(i) = normal(rng);
  return Eigen::MatrixXd::Identity(n, n) - 2.0 * u * u.transpose() / u.squaredNorm();
}

// A covariance like CMA-ES's after many updates: symmetric positive definite, condition 1e6.
Eigen::MatrixXd random_covariance(Eigen::Index n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd g(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) g(i, j) = normal(rng);
  }
  const Eigen::MatrixXd q = g.householderQr().householderQ();
  Eigen::VectorXd values(n);
  for (Eigen::Index i = 0; i < n; ++i) values(i) = std::pow(10.0, 6.0 * static_cast<double>(i) / static_cast<double>(n - 1));
  return with_spectrum(values, q);
}

double orthonormality_error(const Eigen::MatrixXd& v) {
  return (v.transpose() * v - Eigen::MatrixXd::Identity(v.cols(), v.cols())).cwiseAbs().maxCoeff();
}

TEST(SymmetricEigen, ADiagonalMatrixNeedsNoStepAndIsSortedAscending) {
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3, 3);
  a.diagonal() << 3.0, -1.0, 2.0;
  const SymmetricEigen e = symmetric_eigen(a);
  EXPECT_EQ(e.iterations, 0);
  EXPECT_EQ(e.values, Eigen::Vector3d(-1.0, 2.0, 3.0));
  Eigen::MatrixXd permutation = Eigen::MatrixXd::Zero(3, 3);
  permutation(1, 0) = permutation(2, 1) = permutation(0, 2) = 1.0;
  EXPECT_EQ(e.vectors, permutation);
}

TEST(SymmetricEigen, TwoByTwoMatchesTheClosedForm) {
  Eigen::MatrixXd a(2, 2);
  a << 2.0, 1.0, 1.0, 2.0;
  const SymmetricEigen e = symmetric_eigen(a);
  EXPECT_DOUBLE_EQ(e.values(0), 1.0);
  EXPECT_DOUBLE_EQ(e.values(1), 3.0);
  const double h = std::sqrt(0.5);
  EXPECT_NEAR(std::abs(e.vectors(0, 0)), h, 2.3e-16);
  EXPECT_NEAR(e.vectors(0, 0), -e.vectors(1, 0), 2.3e-16);  // (1, -1) / sqrt 2 for 1
  EXPECT_NEAR(e.vectors(0, 1), e.vectors(1, 1), 2.3e-16);  // (1, 1) / sqrt 2 for 3
}

TEST(SymmetricEigen, RecoversAKnownSpectrumAndItsEigenvectors) {
  const Eigen::Index n = 12;
  Eigen::VectorXd values(n);
  for (Eigen::Index i = 0; i < n; ++i) values(i) = static_cast<double>(i) - 4.0;  // negative and zero too
  const Eigen::MatrixXd q = householder(n, 7);
  const SymmetricEigen e = symmetric_eigen(with_spectrum(values, q));
  for (Eigen::Index i = 0; i < n; ++i) {
    EXPECT_NEAR(e.values(i), values(i), 1e-13) << i;
    // Each eigenvector is a column of Q up to its sign.
    const double sign = e.vectors.col(i).dot(q.col(i)) < 0.0 ? -1.0 : 1.0;
    EXPECT_LT((e.vectors.col(i) - sign * q.col(i)).cwiseAbs().maxCoeff(), 1e-13) << i;
  }
  EXPECT_LT(orthonormality_error(e.vectors), 1e-14);
}

TEST(SymmetricEigen, RepeatedEigenvaluesGiveAnOrthonormalBasisOfEachEigenspace) {
  const Eigen::Index n = 6;
  Eigen::VectorXd values(n);
  values << 1.0, 1.0, 1.0, 5.0, 5.0, 9.0;
  const Eigen::MatrixXd a = with_spectrum(values, householder(n, 3));
  const SymmetricEigen e = symmetric_eigen(a);
  EXPECT_LT((e.values - values).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT(orthonormality_error(e.vectors), 1e-14);
  EXPECT_LT((a * e.vectors - e.vectors * e.values.asDiagonal()).cwiseAbs().maxCoeff(), 1e-14);
}

// The size CMA-ES decomposes in QD-Meta (222 meta-genes), against Eigen's solver as an
// independent reference; the reconstruction and orthonormality hold to a few ulps times n.
TEST(SymmetricEigen, ACovarianceOfQdMetasSizeAgreesWithEigensSolver) {
  const Eigen::Index n = 222;
  const Eigen::MatrixXd a = random_covariance(n, 11);
  const SymmetricEigen e = symmetric_eigen(a);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> reference(a);
  ASSERT_EQ(reference.info(), Eigen::Success);
  EXPECT_LT((e.values - reference.eigenvalues()).cwiseAbs().maxCoeff(), 1e-12 * reference.eigenvalues().maxCoeff());
  for (Eigen::Index i = 1; i < n; ++i) EXPECT_LE(e.values(i - 1), e.values(i));
  EXPECT_LT(orthonormality_error(e.vectors), 1e-13);
  const Eigen::MatrixXd rebuilt = e.vectors * e.values.asDiagonal() * e.vectors.transpose();
  EXPECT_LT((rebuilt - a).norm() / a.norm(), 1e-13);
  EXPECT_LT(e.iterations, 3 * n);  // about 2 QR steps per eigenvalue
}

// A graded matrix (entries scaled from 1 down to 1e-12, as a covariance with very different
// step sizes per coordinate is): each eigenvalue, the smallest too, to a relative 1e-12 of a
// long-double reference, not only to 1e-16 of the largest.
TEST(SymmetricEigen, SmallEigenvaluesOfAGradedMatrixKeepTheirRelativeAccuracy) {
  const Eigen::Index n = 4;
  Eigen::MatrixXd h(n, n);  // well conditioned: 4 on the diagonal, 1 off it
  h.setConstant(1.0);
  h.diagonal().setConstant(4.0);
  Eigen::VectorXd scale(n);
  scale << 1.0, 1e-2, 1e-4, 1e-6;
  const Eigen::MatrixXd a = scale.asDiagonal() * h * scale.asDiagonal();
  // Reference in long double through the same similarity: eigenvalues of the scaled matrix by
  // Eigen's solver in long double precision.
  const Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic> wide = a.cast<long double>();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>> reference(wide);
  const SymmetricEigen e = symmetric_eigen(a);
  for (Eigen::Index i = 0; i < n; ++i) {
    const long double exact = reference.eigenvalues()(i);
    EXPECT_LT(std::abs(static_cast<long double>(e.values(i)) - exact) / exact, 1e-12L) << i;
  }
}

TEST(SymmetricEigen, ReadsOnlyTheLowerTriangle) {
  const Eigen::MatrixXd a = random_covariance(9, 5);
  Eigen::MatrixXd lower_only = a;
  lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(std::numeric_limits<double>::quiet_NaN());
  const SymmetricEigen x = symmetric_eigen(a);
  const SymmetricEigen y = symmetric_eigen(lower_only);
  EXPECT_EQ(x.values, y.values);
  EXPECT_EQ(x.vectors, y.vectors);
}

TEST(SymmetricEigen, EmptyAndOneByOne) {
  const SymmetricEigen empty = symmetric_eigen(Eigen::MatrixXd(0, 0));
  EXPECT_EQ(empty.values.size(), 0);
  EXPECT_EQ(empty.iterations, 0);
  const SymmetricEigen one = symmetric_eigen(Eigen::MatrixXd::Constant(1, 1, -2.5));
  EXPECT_EQ(one.values(0), -2.5);
  EXPECT_EQ(one.vectors(0, 0), 1.0);
}

TEST(SymmetricEigen, BadInputIsRefusedAndNonConvergenceReported) {
  EXPECT_INPUT_ERROR(symmetric_eigen(Eigen::MatrixXd::Zero(2, 3)),
                     "symmetric_eigen: the matrix is 2x3, expected a square one");
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(3, 3);
  a(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_INPUT_ERROR(symmetric_eigen(a), "symmetric_eigen: entry (2, 1) is inf, expected a finite number");
  try {
    symmetric_eigen(random_covariance(8, 2), 1);
    ADD_FAILURE() << "8 QR steps cannot diagonalise a dense 8x8 matrix";
  } catch (const InputError&) {
    ADD_FAILURE() << "non-convergence is not an input error";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(), "symmetric_eigen: no convergence of the 8x8 matrix in 8 QR steps");
  }
}

}  // namespace
}  // namespace qdmeta
