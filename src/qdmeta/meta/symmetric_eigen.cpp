#include "qdmeta/meta/symmetric_eigen.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

using Index = Eigen::Index;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// sum x_i y_i in four interleaved partial sums, combined as (s0 + s1) + (s2 + s3): a fixed
// order (so fixed bits) that still lets the compiler use one vector register for the four.
double dot(const double* x, const double* y, Index n) {
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  Index i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int lane = 0; lane < 4; ++lane) s[lane] += x[i + lane] * y[i + lane];
  }
  for (int lane = 0; i < n; ++i, ++lane) s[lane] += x[i] * y[i];
  return (s[0] + s[1]) + (s[2] + s[3]);
}

// sqrt(x^2 + y^2) without overflow or underflow in the squares (std::hypot's bits come from
// the C library, which may pick its code by CPU).
double norm2(double x, double y) {
  const double big = std::max(std::abs(x), std::abs(y));
  if (big == 0.0) return 0.0;
  const double a = x / big;
  const double b = y / big;
  return big * std::sqrt(a * a + b * b);
}

// Householder reduction A = Q T Q^T. On return `a` is destroyed, diag / sub hold T (sub[i] is
// T(i + 1, i)) and q holds Q explicitly.
void tridiagonalise(Eigen::MatrixXd& a, std::vector<double>& diag, std::vector<double>& sub, Eigen::MatrixXd& q) {
  const Index n = a.rows();
  // Householder vectors v (v[0] = 1) and their beta, one per column k reduced.
  std::vector<std::vector<double>> vs;
  std::vector<double> betas;
  std::vector<double> p(static_cast<std::size_t>(n));
  std::vector<double> w(static_cast<std::size_t>(n));
  sub.assign(static_cast<std::size_t>(std::max<Index>(n - 1, 0)), 0.0);
  for (Index k = 0; k + 2 < n; ++k) {
    const Index m = n - k - 1;  // the trailing block is rows and columns k + 1 .. n - 1
    double* x = &a(k + 1, k);
    // The reflection I - beta v v^T that maps x to (|x|, 0, ..., 0), v scaled so v[0] = 1.
    // x is scaled by its largest entry first, so that its squares neither overflow nor vanish.
    double scale = 0.0;
    for (Index i = 0; i < m; ++i) scale = std::max(scale, std::abs(x[i]));
    std::vector<double> v(static_cast<std::size_t>(m), 0.0);
    double beta = 0.0;
    double alpha = scale == 0.0 ? 0.0 : x[0];
    if (scale > 0.0) {
      for (Index i = 0; i < m; ++i) v[i] = x[i] / scale;
      const double tail = dot(v.data() + 1, v.data() + 1, m - 1);
      const double head = v[0];
      if (tail == 0.0) {
        alpha = x[0];  // already of the form (alpha, 0, ..., 0)
      } else {
        const double length = std::sqrt(head * head + tail);
        const double v0 = head <= 0.0 ? head - length : -tail / (head + length);
        beta = 2.0 * v0 * v0 / (tail + v0 * v0);
        for (Index i = 1; i < m; ++i) v[i] /= v0;
        alpha = length * scale;
      }
      v[0] = 1.0;
    }
    sub[k] = alpha;
    if (beta != 0.0) {
      // A22 <- H A22 H with p = beta A22 v, w = p - (beta p^T v / 2) v, A22 -= v w^T + w v^T.
      // A22 is kept whole (both triangles), so the product runs down contiguous columns.
      std::fill_n(p.begin(), m, 0.0);
      for (Index j = 0; j < m; ++j) {
        const double* column = &a(k + 1, k + 1 + j);
        const double vj = beta * v[j];
        for (Index i = 0; i < m; ++i) p[i] += column[i] * vj;
      }
      const double half = 0.5 * beta * dot(p.data(), v.data(), m);
      for (Index i = 0; i < m; ++i) w[i] = p[i] - half * v[i];
      for (Index j = 0; j < m; ++j) {
        double* column = &a(k + 1, k + 1 + j);
        const double vj = v[j];
        const double wj = w[j];
        for (Index i = 0; i < m; ++i) column[i] -= v[i] * wj + w[i] * vj;
      }
    }
    vs.push_back(std::move(v));
    betas.push_back(beta);
  }
  diag.resize(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) diag[i] = a(i, i);
  if (n >= 2) sub[n - 2] = a(n - 1, n - 2);
  // Q = H_0 H_1 ... H_{n-3}, built from the right: each H_k touches rows and columns k + 1 on.
  q = Eigen::MatrixXd::Identity(n, n);
  for (Index k = static_cast<Index>(betas.size()) - 1; k >= 0; --k) {
    const double beta = betas[k];
    if (beta == 0.0) continue;
    const std::vector<double>& v = vs[k];
    const Index m = n - k - 1;
    for (Index j = k + 1; j < n; ++j) {
      double* column = &q(k + 1, j);
      const double t = beta * dot(v.data(), column, m);
      for (Index i = 0; i < m; ++i) column[i] -= t * v[i];
    }
  }
}

// A subdiagonal entry too small to matter next to its two diagonal neighbours.
bool negligible(double sub, double left, double right) {
  return std::abs(sub) <= kEpsilon * (std::abs(left) + std::abs(right));
}

// One implicit QR step with a Wilkinson shift on the unreduced block lo..hi of T, chasing the
// bulge down with rotations R_k in the planes (k, k + 1): T <- R T R^T, Z <- Z R^T.
void qr_step(std::vector<double>& diag, std::vector<double>& sub, Index lo, Index hi, Eigen::MatrixXd& z) {
  const Index n = z.rows();
  const double half_gap = (diag[hi - 1] - diag[hi]) / 2.0;
  const double coupling = sub[hi - 1];
  const double root = norm2(half_gap, coupling);
  const double shift = diag[hi] - coupling * (coupling / (half_gap + (half_gap < 0.0 ? -root : root)));
  double x = diag[lo] - shift;
  double y = sub[lo];
  for (Index k = lo; k < hi; ++k) {
    // The rotation [c s; -s c] with [c s; -s c] (x, y)^T = (r, 0)^T.
    const double r = norm2(x, y);
    const double c = r == 0.0 ? 1.0 : x / r;
    const double s = r == 0.0 ? 0.0 : y / r;
    if (k > lo) sub[k - 1] = r;  // the bulge T(k + 1, k - 1) is now zero
    const double a = diag[k];
    const double b = sub[k];
    const double d = diag[k + 1];
    const double cs = c * s;
    diag[k] = (c * c * a + 2.0 * cs * b) + s * s * d;
    diag[k + 1] = (s * s * a - 2.0 * cs * b) + c * c * d;
    sub[k] = cs * (d - a) + (c * c - s * s) * b;
    if (k + 1 < hi) {
      const double e = sub[k + 1];
      x = sub[k];
      y = s * e;  // the bulge T(k + 2, k)
      sub[k + 1] = c * e;
    }
    double* zk = &z(0, k);
    double* zk1 = &z(0, k + 1);
    for (Index i = 0; i < n; ++i) {
      const double u = zk[i];
      const double t = zk1[i];
      zk[i] = c * u + s * t;
      zk1[i] = c * t - s * u;
    }
  }
}

}  // namespace

SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& matrix, int max_iterations_per_value) {
  const Index n = matrix.rows();
  if (matrix.cols() != n) {
    throw InputError(fmt::format("symmetric_eigen: the matrix is {}x{}, expected a square one", n, matrix.cols()));
  }
  Eigen::MatrixXd a(n, n);  // whole and symmetric, mirrored from the lower triangle
  for (Index j = 0; j < n; ++j) {
    for (Index i = j; i < n; ++i) {
      const double value = matrix(i, j);
      if (!std::isfinite(value)) {
        throw InputError(fmt::format("symmetric_eigen: entry ({}, {}) is {}, expected a finite number", i, j, value));
      }
      a(i, j) = value;
      a(j, i) = value;
    }
  }
  std::vector<double> diag;
  std::vector<double> sub;
  Eigen::MatrixXd z;
  tridiagonalise(a, diag, sub, z);
  SymmetricEigen result;
  const long long max_iterations = static_cast<long long>(max_iterations_per_value) * std::max<Index>(n, 1);
  Index hi = n - 1;
  while (hi > 0) {
    // Deflate from the bottom, then find where the unreduced block ending at hi starts.
    if (negligible(sub[hi - 1], diag[hi - 1], diag[hi])) {
      sub[hi - 1] = 0.0;
      --hi;
      continue;
    }
    Index lo = hi - 1;
    while (lo > 0 && !negligible(sub[lo - 1], diag[lo - 1], diag[lo])) --lo;
    if (lo > 0) sub[lo - 1] = 0.0;
    if (result.iterations == max_iterations) {
      throw Error(fmt::format("symmetric_eigen: no convergence of the {}x{} matrix in {} QR steps", n, n,
                              max_iterations));
    }
    ++result.iterations;
    qr_step(diag, sub, lo, hi, z);
  }
  std::vector<Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Index{0});
  std::stable_sort(order.begin(), order.end(), [&diag](Index x, Index y) { return diag[x] < diag[y]; });
  result.values.resize(n);
  result.vectors.resize(n, n);
  for (Index k = 0; k < n; ++k) {
    const Index from = order[static_cast<std::size_t>(k)];
    result.values(k) = diag[from];
    std::copy_n(&z(0, from), n, &result.vectors(0, k));
  }
  return result;
}

}  // namespace qdmeta
