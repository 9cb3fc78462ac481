#include "qdmeta/featuremap/network_kernel.hpp"

#include <algorithm>
#include <vector>

#include "qdmeta/featuremap/neural_feature_map.hpp"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define QDMETA_NETWORK_AVX2 1
#endif

namespace qdmeta {
namespace {

#if defined(QDMETA_NETWORK_AVX2)

// scaled_sigmoid() on eight lanes, operation for operation (fast_exp's clamps as max/min with
// the constant first, so a NaN propagates as in the scalar ternaries; 1 + p * 2^k fused, as GCC
// contracts the scalar expression).
inline __m256 sigmoid8(__m256 x, __m256 neg_scale) {
  __m256 t = _mm256_mul_ps(neg_scale, x);
  t = _mm256_max_ps(_mm256_set1_ps(-87.3f), t);
  t = _mm256_min_ps(_mm256_set1_ps(88.3f), t);
  const __m256 round = _mm256_set1_ps(12582912.0f);
  const __m256 shifted = _mm256_fmadd_ps(t, _mm256_set1_ps(1.44269504088896341f), round);
  const __m256 k = _mm256_sub_ps(shifted, round);
  const __m256i ki = _mm256_sub_epi32(_mm256_castps_si256(shifted), _mm256_castps_si256(round));
  __m256 r = _mm256_fmadd_ps(k, _mm256_set1_ps(-0.693359375f), t);
  r = _mm256_fmadd_ps(k, _mm256_set1_ps(2.12194440e-4f), r);
  __m256 p = _mm256_set1_ps(1.9875691500e-4f);
  p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(1.3981999507e-3f));
  p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(8.3334519073e-3f));
  p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(4.1665795894e-2f));
  p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(1.6666665459e-1f));
  p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(5.0000001201e-1f));
  const __m256 one = _mm256_set1_ps(1.0f);
  p = _mm256_fmadd_ps(_mm256_mul_ps(p, r), r, _mm256_add_ps(r, one));
  const __m256 scale = _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_add_epi32(ki, _mm256_set1_epi32(127)), 23));
  return _mm256_div_ps(one, _mm256_fmadd_ps(p, scale, one));
}

// J units of one layer for 16 rows: out[j][0..16) = bias + sum_k w[j][k] in[k][0..16).
// Accumulators stay in registers (2 J of them); each broadcast weight serves two vectors.
template <int J>
inline void layer_chunk(const Real* w, Index inputs, Real bias, const Real* in, Index in_ld, Real* out,
                        Index out_ld) {
  __m256 a[J], b[J];
  for (int j = 0; j < J; ++j) a[j] = b[j] = _mm256_set1_ps(bias);
  for (Index k = 0; k < inputs; ++k) {
    const __m256 x0 = _mm256_loadu_ps(in + k * in_ld);
    const __m256 x1 = _mm256_loadu_ps(in + k * in_ld + 8);
    for (int j = 0; j < J; ++j) {
      const __m256 wv = _mm256_broadcast_ss(w + j * inputs + k);
      a[j] = _mm256_fmadd_ps(wv, x0, a[j]);
      b[j] = _mm256_fmadd_ps(wv, x1, b[j]);
    }
  }
  for (int j = 0; j < J; ++j) {
    _mm256_storeu_ps(out + j * out_ld, a[j]);
    _mm256_storeu_ps(out + j * out_ld + 8, b[j]);
  }
}

// A whole layer for 16 rows, its units in chunks of at most five (ten accumulators, two inputs
// and a weight fill 13 of the 16 registers).
void layer16(const Real* w, Index units, Index inputs, Real bias, Real scale, const Real* in, Index in_ld, Real* out,
             Index out_ld) {
  const Index chunks = (units + 4) / 5;
  Index j0 = 0;
  for (Index c = 0; c < chunks; ++c) {
    const Index j1 = (c + 1) * units / chunks;
    const Real* wc = w + j0 * inputs;
    Real* oc = out + j0 * out_ld;
    switch (j1 - j0) {
      case 1: layer_chunk<1>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 2: layer_chunk<2>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 3: layer_chunk<3>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 4: layer_chunk<4>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      default: layer_chunk<5>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
    }
    j0 = j1;
  }
  const __m256 neg_scale = _mm256_set1_ps(-scale);
  // The sigmoids in a pass of their own, the sums reloaded from L1: interleaved with the
  // accumulators they spilled registers (measured: this way the kernel is 20% faster).
  for (Index j = 0; j < units; ++j)
    for (Index r = 0; r < kKernelRows; r += 8)
      _mm256_storeu_ps(out + j * out_ld + r, sigmoid8(_mm256_loadu_ps(out + j * out_ld + r), neg_scale));
}

#else

// Without AVX2 and FMA: the scalar definition, one row (column) at a time.
void layer_scalar(const Real* w, Index units, Index inputs, Real bias, Real scale, const Real* in, Index in_ld,
                  Index count, Real* out, Index out_ld) {
  for (Index r = 0; r < count; ++r)
    for (Index j = 0; j < units; ++j) {
      Real acc = bias;
      for (Index k = 0; k < inputs; ++k) acc = madd(w[j * inputs + k], in[k * in_ld + r], acc);
      out[j * out_ld + r] = scaled_sigmoid(acc, scale);
    }
}

#endif

}  // namespace

void run_network_t(const NetworkView& net, const Real* base_t, Index base_ld, Index count, Real* target_t,
                   Index target_ld) {
  if (count <= 0) return;
#if defined(QDMETA_NETWORK_AVX2)
  // The hidden layer of 16 rows: on the stack for any realistic network.
  constexpr Index kStackHidden = 64;
  alignas(32) Real stack[kStackHidden * kKernelRows];
  std::vector<Real> heap;
  Real* hidden = stack;
  if (net.hidden > kStackHidden) {
    heap.resize(static_cast<std::size_t>(net.hidden * kKernelRows));
    hidden = heap.data();
  }
  for (Index r = 0; r < count; r += kKernelRows) {
    layer16(net.w1, net.hidden, net.inputs, net.b1, net.scale1, base_t + r, base_ld, hidden, kKernelRows);
    layer16(net.w2, net.outputs, net.hidden, net.b2, net.scale2, hidden, kKernelRows, target_t + r, target_ld);
  }
#else
  const Index n = padded_rows(count);
  std::vector<Real> hidden(static_cast<std::size_t>(net.hidden * n));
  layer_scalar(net.w1, net.hidden, net.inputs, net.b1, net.scale1, base_t, base_ld, n, hidden.data(), n);
  layer_scalar(net.w2, net.outputs, net.hidden, net.b2, net.scale2, hidden.data(), n, n, target_t, target_ld);
#endif
}

}  // namespace qdmeta
