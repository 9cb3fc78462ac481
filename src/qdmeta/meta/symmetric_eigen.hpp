#pragma once
// Eigenvalues and eigenvectors of a real symmetric matrix (Householder reduction to tridiagonal
// form, then implicit QR steps with Wilkinson shifts: the method of Golub and Van Loan,
// "Matrix Computations", sections 8.3.1 and 8.3.2), written so that its bits do not depend on
// the CPU or on how the compiler vectorises: every sum runs in an order fixed by the code, and
// the file is compiled with -ffp-contract=off (no fused multiply-adds), so the result is the same
// on any IEEE-754 machine. CMA-ES decomposes its covariance with it: a library solver (Eigen's)
// picks its blocking and reduction order from the instruction set, and QD-Meta's results then
// changed from one CPU model to the next.
#include "qdmeta/core/eigen.hpp"

namespace qdmeta {

struct SymmetricEigen {
  Eigen::VectorXd values;   // ascending; ties keep the order in which they were found
  Eigen::MatrixXd vectors;  // orthonormal columns, vectors.col(i) belongs to values(i)
  int iterations = 0;       // implicit QR steps taken on the tridiagonal matrix
};

// Decomposes the symmetric matrix given by the lower triangle of `matrix` (the upper one is
// ignored). Throws InputError for a matrix that is not square or has a non-finite entry in its
// lower triangle, and Error if the QR steps do not converge within `max_iterations_per_value`
// times n steps (they take about 2 per eigenvalue; the cap guards against a bug).
SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& matrix, int max_iterations_per_value = 30);

}  // namespace qdmeta
