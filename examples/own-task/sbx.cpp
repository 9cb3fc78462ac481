#include "sbx.hpp"

#include <qdmeta/core/rng.hpp>
#include <qdmeta/plugin/part_registries.hpp>

#include <algorithm>
#include <cmath>

namespace arm {
namespace {

// SBX's spread factor for a uniform draw u in [0, 1): the inverse of its distribution function
// F (density (eta + 1) / 2 beta^eta up to 1, (eta + 1) / 2 beta^-(eta + 2) beyond), truncated
// to [0, max_spread] by inverting F at u F(max_spread). max_spread >= 1.
double spread(double u, double eta, double max_spread) {
  const double p = u * (1.0 - 0.5 * std::pow(max_spread, -(eta + 1.0)));
  const double root = 1.0 / (eta + 1.0);
  return p <= 0.5 ? std::pow(2.0 * p, root) : std::pow(0.5 / (1.0 - p), root);
}

// One gene of an offspring of genes x (the parent's) and y (the partner's).
double cross_gene(double x, double y, double eta, qdmeta::Rng& rng) {
  if (rng.uniform() < 0.5) return x;  // this gene is not crossed
  const double lo = std::min(x, y), hi = std::max(x, y), distance = hi - lo;
  if (distance == 0.0) return x;
  const double u = rng.uniform();  // one draw for both children, as in the published operator
  const double mean = 0.5 * (lo + hi);
  // The largest spreads that keep the lower child >= 0 and the upper child <= 1.
  const double lower = mean - 0.5 * distance * spread(u, eta, 1.0 + 2.0 * lo / distance);
  const double upper = mean + 0.5 * distance * spread(u, eta, 1.0 + 2.0 * (1.0 - hi) / distance);
  const double child = rng.uniform() < 0.5 ? lower : upper;
  return std::clamp(child, 0.0, 1.0);  // only rounding can cross a bound
}

}  // namespace

qdmeta::VariationFunction sbx(double eta) {
  return [eta](const qdmeta::RowMatrix& parents, const qdmeta::RowMatrix& partners, std::uint64_t seed,
               qdmeta::RowMatrix& offspring) {
    qdmeta::Rng rng(seed);  // the seed is the call's: the same offspring at any thread count
    for (qdmeta::Index r = 0; r < offspring.rows(); ++r)
      for (qdmeta::Index k = 0; k < offspring.cols(); ++k)
        offspring(r, k) = static_cast<qdmeta::Real>(cross_gene(parents(r, k), partners(r, k), eta, rng));
  };
}

qdmeta::VariationFunction read_sbx(qdmeta::ConfigReader& mutation, const qdmeta::Task& /*task*/) {
  return sbx(mutation.number("eta", 20.0, 0.0, qdmeta::kNoUpper, qdmeta::Open::kLower));
}

void register_sbx() { qdmeta::variation_registry().add("sbx", read_sbx); }

}  // namespace arm
