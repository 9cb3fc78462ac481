#pragma once
// What the CMA-ES tests (cma_es_test.cpp, sep_cma_es_test.cpp) minimise: the sphere, and a
// generation's candidates (the columns of x) scored one by one.
#include <functional>

#include "qdmeta/core/eigen.hpp"

namespace qdmeta::test {

inline double sphere(const Eigen::VectorXd& x) { return x.squaredNorm(); }

inline Eigen::VectorXd evaluate(const Eigen::MatrixXd& x, const std::function<double(const Eigen::VectorXd&)>& f) {
  Eigen::VectorXd values(x.cols());
  for (Eigen::Index k = 0; k < x.cols(); ++k) values(k) = f(x.col(k));
  return values;
}

}  // namespace qdmeta::test
