#include "qdmeta/archive/cqd_score.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("cqd_score: " + what);
}

bool all_finite(std::span<const double> values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

// The p-norm of a - b over `dim` coordinates (p = infinity: the largest |a_i - b_i|), computed
// as numpy.linalg.norm computes it, so that scores agree with pyribs's to rounding.
double distance(const double* a, const double* b, std::size_t dim, double p) {
  if (std::isinf(p)) {
    double largest = 0.0;
    for (std::size_t i = 0; i < dim; ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
    return largest;
  }
  double sum = 0.0;
  if (p == 2.0) {
    for (std::size_t i = 0; i < dim; ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(sum);
  }
  for (std::size_t i = 0; i < dim; ++i) sum += std::pow(std::abs(a[i] - b[i]), p);
  return std::pow(sum, 1.0 / p);
}

void check_settings(const CqdSettings& s) {
  require(!s.penalties.empty(), "penalties is empty: give at least one penalty in [0, 1]");
  for (double theta : s.penalties)
    require(theta >= 0.0 && theta <= 1.0, fmt::format("penalty {} is outside [0, 1]", theta));
  require(std::isfinite(s.obj_min) && std::isfinite(s.obj_max) && s.obj_max > s.obj_min,
          fmt::format("obj_max ({}) must be finite and above obj_min ({})", s.obj_max, s.obj_min));
  require(std::isfinite(s.dist_max) && s.dist_max > 0.0, fmt::format("dist_max ({}) must be finite and > 0", s.dist_max));
  require(s.dist_ord >= 1.0, fmt::format("dist_ord ({}) must be a norm's order: >= 1, or infinity", s.dist_ord));
}

}  // namespace

std::vector<double> evenly_spaced_penalties(std::size_t count) {
  require(count >= 1, "penalties must be at least 1");
  std::vector<double> penalties(count, 0.0);
  if (count == 1) return penalties;
  const double step = 1.0 / static_cast<double>(count - 1);
  for (std::size_t i = 0; i + 1 < count; ++i) penalties[i] = static_cast<double>(i) * step;
  penalties.back() = 1.0;  // the end point exactly, not (count - 1) * step
  return penalties;
}

CqdScore cqd_score(std::span<const double> objectives, std::span<const double> measures, std::size_t measure_dim,
                   std::span<const double> target_points, std::size_t iterations, const CqdSettings& settings) {
  check_settings(settings);
  const std::size_t num_elites = objectives.size();
  require(measure_dim >= 1, "measure_dim must be at least 1");
  require(num_elites >= 1, "the archive has no elite: the score needs at least one");
  require(measures.size() == num_elites * measure_dim,
          fmt::format("measures has {} values, not {} elites x {} measures", measures.size(), num_elites, measure_dim));
  require(iterations >= 1, "iterations must be at least 1");
  const std::size_t per_iteration = iterations * measure_dim;
  require(!target_points.empty() && target_points.size() % per_iteration == 0,
          fmt::format("target_points has {} values, not iterations ({}) x n x measure_dim ({}) with n >= 1",
                      target_points.size(), iterations, measure_dim));
  require(all_finite(objectives) && all_finite(measures), "the archive's objectives and measures must be finite");
  require(all_finite(target_points), "target_points must be finite");
  const std::size_t targets = target_points.size() / per_iteration;

  std::vector<double> normalised(num_elites);
  const double range = settings.obj_max - settings.obj_min;
  for (std::size_t e = 0; e < num_elites; ++e) normalised[e] = (objectives[e] - settings.obj_min) / range;

  CqdScore result;
  result.scores.assign(iterations, 0.0);
  std::vector<double> scaled_distance(num_elites);  // d(e, t) / dist_max for the current target
  for (std::size_t it = 0; it < iterations; ++it) {
    // Per target, then per penalty: each (target, penalty) term is one max over the elites.
    std::vector<double> per_penalty(settings.penalties.size(), 0.0);
    for (std::size_t t = 0; t < targets; ++t) {
      const double* target = target_points.data() + (it * targets + t) * measure_dim;
      for (std::size_t e = 0; e < num_elites; ++e)
        scaled_distance[e] =
            distance(measures.data() + e * measure_dim, target, measure_dim, settings.dist_ord) / settings.dist_max;
      for (std::size_t k = 0; k < settings.penalties.size(); ++k) {
        const double theta = settings.penalties[k];
        double best = -std::numeric_limits<double>::infinity();
        for (std::size_t e = 0; e < num_elites; ++e) best = std::max(best, normalised[e] - theta * scaled_distance[e]);
        per_penalty[k] += best;
      }
    }
    for (double term : per_penalty) result.scores[it] += term;
  }
  double sum = 0.0;
  for (double s : result.scores) sum += s;
  result.mean = sum / static_cast<double>(iterations);
  return result;
}

}  // namespace qdmeta
