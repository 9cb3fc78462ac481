#include "qdmeta/featuremap/neural_feature_map.hpp"

#include <fmt/format.h>

#include <algorithm>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "qdmeta/core/params.hpp"

namespace qdmeta {
namespace {

// acc[r] += sum_{k in [k0, k0 + 4)} w[k] in[k][r], one fused multiply-add per k, in k order.
inline void accumulate4(const Real* w, const Real* __restrict in, Index count, Real* __restrict acc) {
  const Real w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3];
  const Real* __restrict x0 = in;
  const Real* __restrict x1 = x0 + count;
  const Real* __restrict x2 = x1 + count;
  const Real* __restrict x3 = x2 + count;
  for (Index r = 0; r < count; ++r)
    acc[r] = madd(w3, x3[r], madd(w2, x2[r], madd(w1, x1[r], madd(w0, x0[r], acc[r]))));
}

// The same for two output units at once: each input load serves two accumulators.
inline void accumulate4x2(const Real* wa, const Real* wb, const Real* __restrict in, Index count,
                          Real* __restrict acc_a, Real* __restrict acc_b) {
  const Real a0 = wa[0], a1 = wa[1], a2 = wa[2], a3 = wa[3];
  const Real b0 = wb[0], b1 = wb[1], b2 = wb[2], b3 = wb[3];
  const Real* __restrict x0 = in;
  const Real* __restrict x1 = x0 + count;
  const Real* __restrict x2 = x1 + count;
  const Real* __restrict x3 = x2 + count;
  for (Index r = 0; r < count; ++r) {
    const Real v0 = x0[r], v1 = x1[r], v2 = x2[r], v3 = x3[r];
    acc_a[r] = madd(a3, v3, madd(a2, v2, madd(a1, v1, madd(a0, v0, acc_a[r]))));
    acc_b[r] = madd(b3, v3, madd(b2, v2, madd(b1, v1, madd(b0, v0, acc_b[r]))));
  }
}

// out[j][r] = S(bias + sum_k w[j][k] in[k][r]) for every output unit j and row r. Each sum
// starts from the bias and adds the inputs in k order by fused multiply-adds, whatever the
// blocking: the rows lie across the SIMD lanes (the loops over r vectorise), and units are taken
// two at a time and inputs four at a time only to save loads and stores.
void dense_sigmoid_layer(const Real* w, Index outputs, Index inputs, Real bias, Real scale,
                         const Real* __restrict in, Index count, Real* __restrict out) {
  std::fill_n(out, outputs * count, bias);
  Index j = 0;
  for (; j + 2 <= outputs; j += 2) {
    const Real* wa = w + j * inputs;
    const Real* wb = wa + inputs;
    Real* acc_a = out + j * count;
    Real* acc_b = acc_a + count;
    Index k = 0;
    for (; k + 4 <= inputs; k += 4) accumulate4x2(wa + k, wb + k, in + k * count, count, acc_a, acc_b);
    for (; k < inputs; ++k) {
      const Real* __restrict x = in + k * count;
      const Real ka = wa[k], kb = wb[k];
      for (Index r = 0; r < count; ++r) {
        acc_a[r] = madd(ka, x[r], acc_a[r]);
        acc_b[r] = madd(kb, x[r], acc_b[r]);
      }
    }
  }
  for (; j < outputs; ++j) {
    const Real* wj = w + j * inputs;
    Real* __restrict acc = out + j * count;
    Index k = 0;
    for (; k + 4 <= inputs; k += 4) accumulate4(wj + k, in + k * count, count, acc);
    for (; k < inputs; ++k) {
      const Real* __restrict x = in + k * count;
      const Real wk = wj[k];
      for (Index r = 0; r < count; ++r) acc[r] = madd(wk, x[r], acc[r]);
    }
  }
  Real* __restrict all = out;
  for (Index i = 0; i < outputs * count; ++i) all[i] = scaled_sigmoid(all[i], scale);
}

}  // namespace

void transpose_rows(const Real* rows, Index count, Index cols, Real* out) {
  Index k = 0;
#if defined(__AVX2__)
  // 8 x 8 tiles in registers: eight row loads, a shuffle network, eight column stores.
  const Index whole_rows = count - count % 8;
  for (; k + 8 <= cols; k += 8) {
    for (Index r = 0; r < whole_rows; r += 8) {
      const Real* in = rows + r * cols + k;
      __m256 a0 = _mm256_loadu_ps(in), a1 = _mm256_loadu_ps(in + cols), a2 = _mm256_loadu_ps(in + 2 * cols),
             a3 = _mm256_loadu_ps(in + 3 * cols), a4 = _mm256_loadu_ps(in + 4 * cols),
             a5 = _mm256_loadu_ps(in + 5 * cols), a6 = _mm256_loadu_ps(in + 6 * cols),
             a7 = _mm256_loadu_ps(in + 7 * cols);
      const __m256 t0 = _mm256_unpacklo_ps(a0, a1), t1 = _mm256_unpackhi_ps(a0, a1);
      const __m256 t2 = _mm256_unpacklo_ps(a2, a3), t3 = _mm256_unpackhi_ps(a2, a3);
      const __m256 t4 = _mm256_unpacklo_ps(a4, a5), t5 = _mm256_unpackhi_ps(a4, a5);
      const __m256 t6 = _mm256_unpacklo_ps(a6, a7), t7 = _mm256_unpackhi_ps(a6, a7);
      const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xEE);
      const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xEE);
      const __m256 u4 = _mm256_shuffle_ps(t4, t6, 0x44), u5 = _mm256_shuffle_ps(t4, t6, 0xEE);
      const __m256 u6 = _mm256_shuffle_ps(t5, t7, 0x44), u7 = _mm256_shuffle_ps(t5, t7, 0xEE);
      Real* o = out + k * count + r;
      _mm256_storeu_ps(o, _mm256_permute2f128_ps(u0, u4, 0x20));
      _mm256_storeu_ps(o + count, _mm256_permute2f128_ps(u1, u5, 0x20));
      _mm256_storeu_ps(o + 2 * count, _mm256_permute2f128_ps(u2, u6, 0x20));
      _mm256_storeu_ps(o + 3 * count, _mm256_permute2f128_ps(u3, u7, 0x20));
      _mm256_storeu_ps(o + 4 * count, _mm256_permute2f128_ps(u0, u4, 0x31));
      _mm256_storeu_ps(o + 5 * count, _mm256_permute2f128_ps(u1, u5, 0x31));
      _mm256_storeu_ps(o + 6 * count, _mm256_permute2f128_ps(u2, u6, 0x31));
      _mm256_storeu_ps(o + 7 * count, _mm256_permute2f128_ps(u3, u7, 0x31));
    }
    for (Index kk = k; kk < k + 8; ++kk)  // the last count % 8 rows
      for (Index r = whole_rows; r < count; ++r) out[kk * count + r] = rows[r * cols + kk];
  }
#endif
  for (; k < cols; ++k) {  // columns left over (all of them without AVX2)
    Real* __restrict col = out + k * count;
    const Real* __restrict in = rows + k;
    for (Index r = 0; r < count; ++r) col[r] = in[r * cols];
  }
}

void NeuralFeatureMapShape::validate() const {
  require_at_least("feature-map inputs (base features)", inputs, Index{1});
  require_at_least("feature_map.hidden", hidden, Index{1});
  require_at_least("feature-map outputs (target features)", outputs, Index{1});
  if (!(alpha > 0.0) || !std::isfinite(alpha))
    throw InputError(fmt::format("feature_map.alpha = {} is out of range: must be finite and above 0", alpha));
}

NeuralFeatureMap::NeuralFeatureMap(NeuralFeatureMapShape shape, std::span<const double> weights)
    : shape_(shape) {
  shape_.validate();
  const Index k = shape_.weight_count();
  if (static_cast<Index>(weights.size()) != k)
    throw InputError(fmt::format(
        "neural feature-map: got {} weights, but {} inputs, {} hidden units and {} outputs need K = {}*{} + 1 + {}*{} + 1 = {}",
        weights.size(), shape_.inputs, shape_.hidden, shape_.outputs, shape_.hidden, shape_.inputs,
        shape_.outputs, shape_.hidden, k));
  for (std::size_t i = 0; i < weights.size(); ++i)
    if (!std::isfinite(weights[i]))
      throw InputError(fmt::format("neural feature-map: weight {} is {}: must be finite", i, weights[i]));
  const auto n1 = static_cast<std::size_t>(shape_.hidden * shape_.inputs);
  const auto n2 = static_cast<std::size_t>(shape_.outputs * shape_.hidden);
  w1_.assign(weights.begin(), weights.begin() + static_cast<std::ptrdiff_t>(n1));
  b1_ = static_cast<Real>(weights[n1]);
  w2_.assign(weights.begin() + static_cast<std::ptrdiff_t>(n1 + 1),
             weights.begin() + static_cast<std::ptrdiff_t>(n1 + 1 + n2));
  b2_ = static_cast<Real>(weights[n1 + 1 + n2]);
  scale1_ = static_cast<Real>(shape_.alpha / static_cast<double>(shape_.inputs + 1));
  scale2_ = static_cast<Real>(shape_.alpha / static_cast<double>(shape_.hidden + 1));
}

void NeuralFeatureMap::map_transposed(const Real* base_t, Index count, Real* scratch, Real* target) const {
  Real* hidden = scratch;                           // N_h x count
  Real* out = scratch + shape_.hidden * count;      // N_t x count
  dense_sigmoid_layer(w1_.data(), shape_.hidden, shape_.inputs, b1_, scale1_, base_t, count, hidden);
  dense_sigmoid_layer(w2_.data(), shape_.outputs, shape_.hidden, b2_, scale2_, hidden, count, out);
  const Index nt = shape_.outputs;
  for (Index t = 0; t < nt; ++t)
    for (Index r = 0; r < count; ++r) target[r * nt + t] = out[t * count + r];
}

void NeuralFeatureMap::map(const Real* base, Index count, Real* target) const {
  if (count <= 0) return;
  const Index nb = shape_.inputs;
  const Index block = std::min(count, kBlockRows);
  std::vector<Real> buffer(static_cast<std::size_t>(nb * block + scratch_size(block)));
  Real* base_t = buffer.data();
  Real* scratch = buffer.data() + nb * block;
  for (Index first = 0; first < count; first += block) {
    const Index n = std::min(block, count - first);
    const Real* rows = base + first * nb;
    transpose_rows(rows, n, nb, base_t);
    map_transposed(base_t, n, scratch, target + first * shape_.outputs);
  }
}

}  // namespace qdmeta
