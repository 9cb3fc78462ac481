#pragma once
// Mutation operators over a block of genotypes in [0, 1]. Each gene mutates independently with
// probability `rate`; the mask is drawn by geometric skipping over the whole block, so the cost
// is proportional to the number of mutated genes, not to the block size. The iso+line operator
// is the exception: it varies every gene of a parent along the line to a second parent, so its
// callers draw two parents per offspring (needs_two_parents) and call apply_iso_line. So does a
// variation operator of the caller's (core/variation.hpp), which replaces the built-in kinds.
#include <cstdint>
#include <string>
#include <string_view>

#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"
#include "qdmeta/core/variation.hpp"

namespace qdmeta {

enum class MutationKind {
  kGaussian,        // gene += N(0, sigma), clamped to [0, 1] (Rastrigin)
  kDiscreteStep,    // gene moves one step up or down on the grid {0, step, ..., 1}, clamped (RHex, paper)
  kUniformResample, // gene redrawn uniformly on the grid (RHex, the authors' QD-Meta/CVT code)
  kIsoLine          // x_i + iso_sigma N(0, I) + line_sigma N(0, 1) (x_j - x_i), clamped (Vassiliades & Mouret 2018)
};
inline constexpr EnumNames<MutationKind, 4> kMutationKindNames{{{MutationKind::kGaussian, "gaussian"},
                                                                 {MutationKind::kDiscreteStep, "discrete-step"},
                                                                 {MutationKind::kUniformResample, "uniform-resample"},
                                                                 {MutationKind::kIsoLine, "iso-line"}}};

struct MutationParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp).
  static constexpr RealParam kRate{"mutation", "rate", 0.0, 1.0, Open::kNone,
      "probability that each gene mutates (not iso-line, which varies every gene)"};
  static constexpr RealParam kSigma{"mutation", "sigma", 0.0, kNoUpper, Open::kLower,
      "standard deviation of the Gaussian (gaussian only; the authors' Rastrigin code effectively used "
      "0.0025, see docs/fidelity.md)"};
  static constexpr RealParam kStep{"mutation", "step", 0.0, 1.0, Open::kLower,
      "grid step (discrete-step and uniform-resample)"};
  static constexpr RealParam kIsoSigma{"mutation", "iso_sigma", 0.0, kNoUpper, Open::kNone,
      "iso-line: standard deviation of the isotropic noise added to every gene"};
  static constexpr RealParam kLineSigma{"mutation", "line_sigma", 0.0, kNoUpper, Open::kNone,
      "iso-line: standard deviation of the step along the line from the first parent to the second"};
  MutationKind kind = MutationKind::kGaussian;  // which operator
  double rate = 0.10;                           // per-gene mutation probability, in [0, 1] (not iso-line)
  double sigma = 0.05;                          // Gaussian SD (kGaussian only), > 0
  double step = 0.025;                          // grid step (kDiscreteStep, kUniformResample), in (0, 1]
  double iso_sigma = 0.01;                      // kIsoLine: SD of the isotropic noise on every gene, >= 0
  double line_sigma = 0.2;                      // kIsoLine: SD of the step along x_j - x_i, >= 0
  // A caller's operator (core/variation.hpp): when set, it makes every offspring, and the fields
  // above are unused; `variation_name` names it in messages ([mutation] kind).
  VariationFunction variation;
  std::string variation_name;
  void validate() const;
};

class Mutation {
 public:
  explicit Mutation(MutationParams params);
  const MutationParams& params() const { return params_; }
  // True for iso+line: each offspring needs a second parent and apply_iso_line, not apply.
  bool needs_two_parents() const { return params_.kind == MutationKind::kIsoLine && !plugged(); }
  // True when the caller's operator makes the offspring (vary(), not apply or apply_iso_line).
  bool plugged() const { return static_cast<bool>(params_.variation); }
  // The caller's operator on rows of `parents` and `partners` (sized alike), writing `offspring`
  // (sized already); InputError naming the operator when it changed the shape or wrote a gene
  // outside [0, 1] (NaN included).
  void vary(const RowMatrix& parents, const RowMatrix& partners, std::uint64_t seed, RowMatrix& offspring) const;
  // Mutates every row of `genotypes` in place.
  void apply(RowMatrix& genotypes, Rng& rng) const;
  // Mutates `count` contiguous genes in place (the rows of a block, flattened).
  void apply(Real* genes, Index count, Rng& rng) const;
  // Iso+line: `genes` (n of them) holds the first parent x_i and becomes
  // clamp(x_i + iso_sigma z + line_sigma w (x_j - x_i), 0, 1), x_j = `other`. The draws, all
  // rng.normal_float(): w first, then z_0 .. z_{n-1}.
  void apply_iso_line(Real* genes, const Real* other, Index n, Rng& rng) const;

 private:
  Real mutate_gene(Real gene, Rng& rng) const;
  void apply_gaussian(Real* genes, std::uint64_t count, Rng& rng) const;  // 0 < rate < 1
  MutationParams params_;
  float inv_log1m_rate_ = 0.0f;
  int grid_steps_ = 0;  // number of steps between 0 and 1 on the discrete grid
};

}  // namespace qdmeta
