#pragma once
// The two domains of the CMA-MAE paper (Fontaine & Nikolaidis 2023) that bench/peers runs, as
// its experiments define them (the authors' lin_proj.py and arm.py; common.py has the same in
// numpy). Genes are unbounded; objectives are normalised so that 100 is the optimum.
//
// Linear-projection sphere, n = 100 genes: objective 100 (W - S) / W with S = sum (x_i - 2.048)^2
// and W = n (5.12 + 2.048)^2 (so x = -5.12 in every gene scores 0); measures are the sums of the
// first and of the last n/2 genes after each gene outside [-5.12, 5.12] is folded to 5.12 / x_i,
// on a 100 x 100 grid over [-n/2 5.12, n/2 5.12]^2.
//
// Planar arm, n = 100 joints of length 1: gene x_j is joint j's angle relative to the link
// before; objective 100 (1 - Var(x)) (population variance); measures are the end effector's
// (x, y) = sum_j (cos, sin)(x_1 + ... + x_j), on a 100 x 100 grid over [-n, n]^2.
#include <cmath>
#include <string_view>
#include <vector>

#include "qdmeta/core/types.hpp"

namespace qdmeta::peers {

inline constexpr double kSphereBound = 5.12;
inline constexpr double kSphereShift = 0.4 * kSphereBound;

struct CmaDomain {
  std::string_view name;
  double measure_bound;  // the grid spans [-measure_bound, measure_bound] in both measures
  double sigma0;         // the paper's initial CMA-ES step size for the domain
};

inline CmaDomain lin_proj_sphere_domain(Index genes) { return {"sphere", genes / 2 * kSphereBound, 0.5}; }
inline CmaDomain arm_domain(Index joints) { return {"arm", static_cast<double>(joints), 0.1}; }

// Objective and the two measures of one solution of `genes` values.
inline void lin_proj_sphere(const Real* x, Index genes, double& objective, double measures[2]) {
  const double worst = static_cast<double>(genes) * (kSphereBound + kSphereShift) * (kSphereBound + kSphereShift);
  double squares = 0.0;
  measures[0] = measures[1] = 0.0;
  for (Index j = 0; j < genes; ++j) {
    const double g = x[j];
    squares += (g - kSphereShift) * (g - kSphereShift);
    measures[j < genes / 2 ? 0 : 1] += std::abs(g) <= kSphereBound ? g : kSphereBound / g;
  }
  objective = 100.0 * (worst - squares) / worst;
}

inline void arm(const Real* x, Index joints, double& objective, double measures[2]) {
  double mean = 0.0;
  for (Index j = 0; j < joints; ++j) mean += x[j];
  mean /= static_cast<double>(joints);
  double variance = 0.0, heading = 0.0;
  measures[0] = measures[1] = 0.0;
  for (Index j = 0; j < joints; ++j) {
    variance += (x[j] - mean) * (x[j] - mean);
    heading += x[j];
    measures[0] += std::cos(heading);
    measures[1] += std::sin(heading);
  }
  objective = 100.0 * (1.0 - variance / static_cast<double>(joints));
}

// Every row of `x` through `evaluate_one`, into the scheduler's float objectives and measures.
template <class Evaluate>
void evaluate_rows(const RowMatrix& x, Evaluate evaluate_one, std::vector<Real>& objectives, RowMatrix& measures) {
  objectives.resize(static_cast<std::size_t>(x.rows()));
  measures.resize(x.rows(), 2);
  for (Index r = 0; r < x.rows(); ++r) {
    double objective = 0.0, m[2];
    evaluate_one(x.row(r).data(), x.cols(), objective, m);
    objectives[static_cast<std::size_t>(r)] = static_cast<Real>(objective);
    measures(r, 0) = static_cast<Real>(m[0]);
    measures(r, 1) = static_cast<Real>(m[1]);
  }
}

}  // namespace qdmeta::peers
