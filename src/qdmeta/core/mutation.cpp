#include "qdmeta/core/mutation.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <utility>

#include "qdmeta/core/fused.hpp"

namespace qdmeta {

void MutationParams::validate() const {
  if (variation) return;  // the caller's operator checks its own parameters
  require(kRate, rate);
  if (kind == MutationKind::kGaussian) require(kSigma, sigma);
  if (kind == MutationKind::kIsoLine) {
    require(kIsoSigma, iso_sigma);
    require(kLineSigma, line_sigma);
  }
  if (kind == MutationKind::kDiscreteStep || kind == MutationKind::kUniformResample) {
    require(kStep, step);
    const double steps = 1.0 / step;
    if (std::abs(steps - std::round(steps)) > 1e-6)
      throw InputError(fmt::format("mutation.step = {} must divide 1 into a whole number of steps", step));
  }
}

Mutation::Mutation(MutationParams params) : params_(std::move(params)) {
  params_.validate();
  if (params_.rate > 0.0 && params_.rate < 1.0) inv_log1m_rate_ = static_cast<float>(1.0 / std::log1p(-params_.rate));
  if (params_.kind == MutationKind::kDiscreteStep || params_.kind == MutationKind::kUniformResample) grid_steps_ = static_cast<int>(std::lround(1.0 / params_.step));
}

Real Mutation::mutate_gene(Real gene, Rng& rng) const {
  switch (params_.kind) {
    case MutationKind::kGaussian: {
      const Real g = fused(static_cast<Real>(params_.sigma), rng.normal_float(), gene);
      return std::clamp(g, Real{0}, Real{1});
    }
    case MutationKind::kDiscreteStep: {
      const long k = std::lround(static_cast<double>(gene) * grid_steps_);
      const long moved = std::clamp<long>(k + ((rng() >> 63) ? 1 : -1), 0, grid_steps_);
      return static_cast<Real>(static_cast<double>(moved) / grid_steps_);
    }
    case MutationKind::kUniformResample: {
      const auto k = static_cast<double>(rng.below(static_cast<std::uint64_t>(grid_steps_) + 1));
      return static_cast<Real>(k / grid_steps_);
    }
    case MutationKind::kIsoLine:
      break;  // needs a second parent: apply() refuses it
  }
  return gene;
}

// The Gaussian operator's loop with everything inlined and the generator in a local copy, so
// that its state stays in registers across the logf calls: the same draws in the same order and
// the same float operations as mutate_gene, so the same bits (tests/core/mutation_test.cpp).
void Mutation::apply_gaussian(Real* genes, std::uint64_t n, Rng& rng) const {
  Rng local = rng;
  const auto sigma = static_cast<Real>(params_.sigma);
  const float inv = inv_log1m_rate_;
  std::uint64_t pos = local.geometric(inv);
  while (pos < n) {
    // Fused as written, so that the bits do not hang on the compiler contracting gene + sigma * z.
    const Real g = fused(sigma, local.normal_float(), genes[pos]);
    genes[pos] = std::clamp(g, Real{0}, Real{1});
    pos += 1 + local.geometric(inv);
  }
  rng = local;
}

void Mutation::apply_iso_line(Real* genes, const Real* other, Index n, Rng& rng) const {
  const auto iso = static_cast<Real>(params_.iso_sigma);
  const Real line = static_cast<Real>(params_.line_sigma) * rng.normal_float();
  for (Index k = 0; k < n; ++k) {
    const Real g = genes[k] + iso * rng.normal_float() + line * (other[k] - genes[k]);
    genes[k] = std::clamp(g, Real{0}, Real{1});
  }
}

void Mutation::vary(const RowMatrix& parents, const RowMatrix& partners, std::uint64_t seed,
                    RowMatrix& offspring) const {
  if (!plugged()) throw Error("Mutation::vary: no variation operator was given (MutationParams::variation)");
  const Index rows = offspring.rows(), cols = offspring.cols();
  params_.variation(parents, partners, seed, offspring);
  const std::string name = params_.variation_name.empty() ? "the variation operator" : params_.variation_name;
  if (offspring.rows() != rows || offspring.cols() != cols)
    throw InputError(fmt::format("mutation kind \"{}\" returned {} x {} offspring for {} x {} parents: keep the shape",
                                 name, offspring.rows(), offspring.cols(), rows, cols));
  const Real* g = offspring.data();
  for (Index i = 0; i < offspring.size(); ++i)
    if (!(g[i] >= Real{0} && g[i] <= Real{1}))  // NaN fails too
      throw InputError(fmt::format("mutation kind \"{}\" wrote gene {} = {} of offspring {}: genes must be in [0, 1]",
                                   name, i % cols, g[i], i / cols));
}

void Mutation::apply(Real* genes, Index count, Rng& rng) const {
  if (plugged()) throw Error("a caller's variation operator makes whole offspring (Mutation::vary), not apply()");
  if (needs_two_parents()) throw Error("the iso-line operator needs two parents per offspring (apply_iso_line)");
  if (params_.rate <= 0.0 || count <= 0) return;
  if (params_.kind == MutationKind::kGaussian && params_.rate < 1.0) {
    apply_gaussian(genes, static_cast<std::uint64_t>(count), rng);
    return;
  }
  if (params_.rate >= 1.0) {
    for (Index i = 0; i < count; ++i) genes[i] = mutate_gene(genes[i], rng);
    return;
  }
  // Position of the next mutated gene: skip a Geometric(rate) number of untouched genes.
  std::uint64_t pos = rng.geometric(inv_log1m_rate_);
  const auto n = static_cast<std::uint64_t>(count);
  while (pos < n) {
    genes[pos] = mutate_gene(genes[pos], rng);
    pos += 1 + rng.geometric(inv_log1m_rate_);
  }
}

void Mutation::apply(RowMatrix& genotypes, Rng& rng) const { apply(genotypes.data(), genotypes.size(), rng); }

}  // namespace qdmeta
