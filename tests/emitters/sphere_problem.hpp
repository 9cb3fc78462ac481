#pragma once
// The emitter tests' benchmark, the linear-projection sphere of the CMA-ME paper (Fontaine et
// al. 2020, as pyribs's sphere example): unbounded genes x in R^10; objective the sphere with its
// optimum at 0.4 * 5.12 in every gene, rescaled so that the box [-5.12, 5.12]^10 maps to
// [0, 100]; measures the sums of the first five and of the last five genes after each gene
// outside [-5.12, 5.12] is folded to 5.12 / x_i (so the outer cells are hard to reach), on a
// 20 x 20 grid over [-25.6, 25.6]^2.
#include <cmath>
#include <string>
#include <vector>

#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta::test {

inline constexpr Index kSphereGenes = 10;
inline constexpr double kSphereBound = 5.12;

inline GridArchiveParams sphere_grid() {
  GridArchiveParams p;
  p.bins = {20, 20};
  p.lower = -kSphereBound * 5;
  p.upper = kSphereBound * 5;
  p.solution_size = kSphereGenes;
  return p;
}

// Objectives and measures of every row of `x`.
inline void evaluate_sphere(const RowMatrix& x, std::vector<Real>& objectives, RowMatrix& measures) {
  const double shift = 0.4 * kSphereBound;
  const double worst = (kSphereBound + shift) * (kSphereBound + shift) * kSphereGenes;
  objectives.resize(static_cast<std::size_t>(x.rows()));
  measures.resize(x.rows(), 2);
  for (Index r = 0; r < x.rows(); ++r) {
    double squares = 0.0, first = 0.0, last = 0.0;
    for (Index j = 0; j < kSphereGenes; ++j) {
      const double g = x(r, j);
      squares += (g - shift) * (g - shift);
      const double folded = std::abs(g) <= kSphereBound ? g : kSphereBound / g;
      (j < kSphereGenes / 2 ? first : last) += folded;
    }
    objectives[static_cast<std::size_t>(r)] = static_cast<Real>(100.0 * (worst - squares) / worst);
    measures(r, 0) = static_cast<Real>(first);
    measures(r, 1) = static_cast<Real>(last);
  }
}

// One ask/tell round of a scheduler on the sphere.
template <class Scheduler>
void sphere_step(Scheduler& scheduler, Rng& rng) {
  std::vector<Real> objectives;
  RowMatrix measures;
  evaluate_sphere(scheduler.ask(rng), objectives, measures);
  scheduler.tell(objectives, measures);
}

// The archive's elites and the scheduler's checkpoint, as bytes.
template <class Scheduler>
std::string checkpoint_bytes(const GridArchive& archive, const Scheduler& scheduler) {
  BinaryWriter out;
  archive.save(out);
  scheduler.save(out);
  return out.bytes();
}

}  // namespace qdmeta::test
