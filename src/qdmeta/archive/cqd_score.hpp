#pragma once
// The Continuous Quality-Diversity score (CQD; Kent, Branke et al., GECCO 2022) of a set of
// elites: for target points t in measure space and penalties theta in [0, 1],
//   CQD = sum over theta, sum over t of  max over elites e of  f^(e) - theta * d(e, t) / dist_max,
// with f^ = (f - obj_min) / (obj_max - obj_min). It rewards an archive for having, near every
// target, an elite that is good, and needs no grid, so that archives of any kind (and of
// different resolutions) compare on one scale. pyribs's cqd_score takes the same arguments; it
// normalises f / (obj_max - obj_min), without subtracting obj_min, so the two agree where
// obj_min = 0 and otherwise differ by obj_min / (obj_max - obj_min) per target and penalty
// (docs/library.md, "CQD score").
#include <cstddef>
#include <span>
#include <vector>

namespace qdmeta {

struct CqdSettings {
  std::vector<double> penalties;  // theta, each in [0, 1] (evenly_spaced_penalties makes them)
  double obj_min = 0.0;
  double obj_max = 1.0;   // > obj_min
  double dist_max = 1.0;  // > 0: the largest distance between two points of measure space
  double dist_ord = 2.0;  // the p of the p-norm distance, >= 1, or infinity (the largest |difference|)
};

struct CqdScore {
  std::vector<double> scores;  // one per iteration (set of target points)
  double mean = 0.0;           // their mean
};

// `count` penalties from 0 to 1, evenly spaced (as numpy.linspace(0, 1, count)); count >= 1.
std::vector<double> evenly_spaced_penalties(std::size_t count);

// The CQD score of `num_elites` elites (objectives[e]; measures row-major, num_elites x
// measure_dim) against `iterations` sets of `targets_per_iteration` target points each
// (target_points row-major, iterations x targets_per_iteration x measure_dim). Refuses, naming
// the argument, a shape that does not fit, no elite, no target, a non-finite input and settings
// outside their ranges.
CqdScore cqd_score(std::span<const double> objectives, std::span<const double> measures, std::size_t measure_dim,
                   std::span<const double> target_points, std::size_t iterations, const CqdSettings& settings);

}  // namespace qdmeta
