#pragma once
// QD-Meta's feature-map (docs/specification.md, QD-Meta): a one-hidden-layer network whose weights are the
// meta-genotype w itself, used directly (no transform):
//   h = S_{N_b}(W1 b + B1),  beta = S_{N_h}(W2 h + B2),  S_N(x) = 1 / (1 + exp(-alpha x / (N + 1))).
// Layout of w: W1 row-major (N_h x N_b), B1 (one scalar shared by the hidden layer), W2
// row-major (N_t x N_h), B2 (one scalar). K = N_h N_b + 1 + N_t N_h + 1.
//
// Every row goes through the same fixed sequence of float operations (fused multiply-adds in
// input order, then the sigmoid below), whatever the block it arrives in: mapping a block equals
// mapping its rows one by one, bit for bit. Archive rebuilds rely on this (rebuild.hpp), and it
// keeps results independent of block sizes and thread counts. The rows of a block are laid
// across SIMD lanes (the block is transposed first) and both layers run in registers
// (network_kernel.hpp); a general matrix-product kernel could not promise equal bits, because
// its edge paths accumulate differently from its main path.
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "qdmeta/core/fused.hpp"
#include "qdmeta/featuremap/feature_map.hpp"
#include "qdmeta/featuremap/network_kernel.hpp"

namespace qdmeta {

// exp(x) in float, branch-free so loops over it vectorise: x = k ln2 + r with |r| <= ln2 / 2,
// exp(r) by Cephes's degree-7 polynomial, 2^k put into the exponent bits. Relative error below
// 2e-7 for x in [-87.3, 88.3]; x is clamped to that range (no infinities, no subnormals).
inline float fast_exp(float x) {
  constexpr float kLog2e = 1.44269504088896341f;
  constexpr float kLn2Hi = 0.693359375f;        // ln 2 split in two so k * kLn2Hi is exact
  constexpr float kLn2Lo = -2.12194440e-4f;
  constexpr float kRound = 12582912.0f;         // 1.5 * 2^23: adding it rounds to an integer
  x = x < -87.3f ? -87.3f : x;
  x = x > 88.3f ? 88.3f : x;
  const float shifted = fused(x, kLog2e, kRound);
  const float k = shifted - kRound;
  const std::int32_t ki = std::bit_cast<std::int32_t>(shifted) - std::bit_cast<std::int32_t>(kRound);
  float r = fused(k, -kLn2Hi, x);
  r = fused(k, -kLn2Lo, r);
  float p = 1.9875691500e-4f;
  p = fused(p, r, 1.3981999507e-3f);
  p = fused(p, r, 8.3334519073e-3f);
  p = fused(p, r, 4.1665795894e-2f);
  p = fused(p, r, 1.6666665459e-1f);
  p = fused(p, r, 5.0000001201e-1f);
  p = fused(p * r, r, r + 1.0f);  // 1 + r + r^2 (1/2 + r/6 + ...)
  const float scale = std::bit_cast<float>(static_cast<std::int32_t>((ki + 127) * (1 << 23)));
  return p * scale;
}

// 1 / (1 + exp(-scale x)) with fast_exp: the base-e form of the sigmoid (the feature-map used it
// until 2026-12-02), kept for comparison; GCC fuses its final 1 + p 2^k on an FMA machine.
inline float scaled_sigmoid(float x, float scale) { return 1.0f / (1.0f + fast_exp(-scale * x)); }

// 2^t in float, branch-free, as a mantissa p and a power of two 2^k (so that 1 + p 2^k can be
// fused): t = k + f with k = round(t) and |f| <= 1/2, 2^f = 1 + f q(f) with q a degree-4
// polynomial fitted for this (minimax in relative error: below 7e-7 on [-1/2, 1/2], exactly 1
// at f = 0). t is clamped to [-125, 125]: no infinities and no subnormals.
struct Exp2Parts {
  float mantissa = 1.0f;  // 2^f, in [0.70, 1.42]
  float power = 1.0f;     // 2^k
};
inline Exp2Parts fast_exp2_parts(float t) {
  constexpr float kRound = 12582912.0f;  // 1.5 * 2^23: adding it rounds to an integer
  t = t < -125.0f ? -125.0f : t;
  t = t > 125.0f ? 125.0f : t;
  const float shifted = t + kRound;
  const float k = shifted - kRound;
  const std::int32_t ki = std::bit_cast<std::int32_t>(shifted) - std::bit_cast<std::int32_t>(kRound);
  const float f = t - k;
  float q = 1.281443634e-3f;
  q = fused(q, f, 9.656608105e-3f);
  q = fused(q, f, 5.551610515e-2f);
  q = fused(q, f, 2.402247787e-1f);
  q = fused(q, f, 6.931468248e-1f);
  Exp2Parts e;
  e.mantissa = fused(f, q, 1.0f);
  e.power = std::bit_cast<float>(static_cast<std::int32_t>((ki + 127) * (1 << 23)));
  return e;
}
inline float fast_exp2(float t) {
  const Exp2Parts e = fast_exp2_parts(t);
  return e.mantissa * e.power;
}

// 1 / (1 + 2^z): the feature-map's sigmoid. NeuralFeatureMap keeps each layer's weights and
// bias multiplied by -alpha log2(e) / (N + 1), so z = -alpha log2(e) x / (N + 1) and this is
// S_N(x) = 1 / (1 + exp(-alpha x / (N + 1))) with six multiply-adds and no multiplication where
// the base-e form needs ten and one. In (0, 1], exactly 1/2 at z = 0.
inline float base2_sigmoid(float z) {
  const Exp2Parts e = fast_exp2_parts(z);
  return 1.0f / fused(e.mantissa, e.power, 1.0f);
}

// out (cols x count, row-major, row k at out + k ld) = the transpose of rows (count x cols, row-major): the layout
// map_transposed() reads. Written column by column so stores are contiguous (a store stride of
// a power of two kilobytes would thrash the L1 cache).
void transpose_rows(const Real* rows, Index count, Index cols, Real* out, Index ld);
// The same with out's rows packed (ld = count).
inline void transpose_rows(const Real* rows, Index count, Index cols, Real* out) {
  transpose_rows(rows, count, cols, out, count);
}

// The network's size. N_b and N_t come from the task and the archive; N_h and alpha_s are
// QD-Meta settings.
struct NeuralFeatureMapShape {
  Index inputs = 0;     // N_b: base features read, >= 1 (20 on Rastrigin)
  Index hidden = 10;    // N_h: hidden units, >= 1
  Index outputs = 0;    // N_t: target features written, >= 1 (the archive's dimensions)
  double alpha = 30.0;  // alpha_s: sigmoid steepness, finite and > 0
  // K = N_h N_b + 1 + N_t N_h + 1 (222 for 20, 10, 2).
  Index weight_count() const { return hidden * inputs + 1 + outputs * hidden + 1; }
  void validate() const;
  bool operator==(const NeuralFeatureMapShape&) const = default;
};

class NeuralFeatureMap final : public FeatureMap {
 public:
  // Rows per block inside map(): the transposed block and the hidden layer stay in L1.
  static constexpr Index kBlockRows = 256;

  // Throws InputError when the shape is invalid, when `weights` does not hold exactly
  // shape.weight_count() values (naming both sizes), or when a weight is not finite.
  NeuralFeatureMap(NeuralFeatureMapShape shape, std::span<const double> weights);

  const NeuralFeatureMapShape& shape() const { return shape_; }
  Index input_size() const override { return shape_.inputs; }
  Index output_size() const override { return shape_.outputs; }
  void map(const Real* base, Index count, Real* target) const override;

  // Building block for map() and for archive rebuilds that share one transposed block among
  // several maps (network_kernel.hpp). base_t: N_b x base_ld row-major (row k holds base
  // feature k of every row); target_t: N_t x target_ld, feature-major too. Both leading
  // dimensions must be at least padded_rows(count); base_t's padding columns are read (keep
  // them finite, e.g. zero) and target_t's are written. Each row's result equals map()'s, for
  // either `rows` (where base_t's rows are: network_kernel.hpp).
  void map_transposed(const Real* base_t, Index base_ld, Index count, Real* target_t, Index target_ld,
                      BaseRows rows = BaseRows::cached) const;

 private:
  NeuralFeatureMapShape shape_;
  // Weights and biases times the layer's -alpha log2(e) / (N + 1), rounded to float once
  // (base2_sigmoid then needs no scaling).
  std::vector<Real> w1_;  // N_h x N_b row-major
  std::vector<Real> w2_;  // N_t x N_h row-major
  Real b1_ = 0;
  Real b2_ = 0;
};

}  // namespace qdmeta
