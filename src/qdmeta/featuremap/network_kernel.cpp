// GCC 12's avx512fintrin.h passes _mm512_undefined_ps() as the masked-off source of max, min and
// shifts and then warns about it at every use (fixed in GCC 13): the pragma must come before the
// first include, which pulls the header in.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13 && defined(__AVX512F__)
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include "qdmeta/featuremap/network_kernel.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "qdmeta/featuremap/neural_feature_map.hpp"

#if defined(__AVX512F__)
#include <immintrin.h>
#define QDMETA_NETWORK_AVX512 1
#elif defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define QDMETA_NETWORK_AVX2 1
#endif

namespace qdmeta {
namespace {

#if defined(QDMETA_NETWORK_AVX512) || defined(QDMETA_NETWORK_AVX2)

// Streamed rows (BaseRows::streamed): each step asks for its features' rows kPrefetchRows ahead
// (BM_NetworkOverDatabase: 1.7-2.0x faster over the database on Zen 5, bench/README.md); on
// cached rows the prefetches only cost, so they are skipped there. A prefetch never
// faults, so one past the database's end is harmless; the address is formed as an integer
// because a pointer past the end of its array would be undefined.
constexpr Index kPrefetchRows = 512;

inline void prefetch_ahead(const Real* base_t, Index base_ld, Index inputs, Index rows) {
  constexpr Index kRowsPerLine = 64 / static_cast<Index>(sizeof(Real));
  const auto first = reinterpret_cast<std::uintptr_t>(base_t) + kPrefetchRows * sizeof(Real);
  for (Index k = 0; k < inputs; ++k)
    for (Index r = 0; r < rows; r += kRowsPerLine)
      _mm_prefetch(reinterpret_cast<const char*>(first + static_cast<std::uintptr_t>(k * base_ld + r) * sizeof(Real)),
                   _MM_HINT_T0);
}

#endif

#if defined(QDMETA_NETWORK_AVX512)

// base2_sigmoid() on sixteen lanes, operation for operation (the clamps as max/min with the
// constant first, so a NaN propagates as in the scalar ternaries).
inline __m512 sigmoid16(__m512 z) {
  __m512 t = _mm512_max_ps(_mm512_set1_ps(-125.0f), z);
  t = _mm512_min_ps(_mm512_set1_ps(125.0f), t);
  const __m512 round = _mm512_set1_ps(12582912.0f);
  const __m512 shifted = _mm512_add_ps(t, round);
  const __m512 k = _mm512_sub_ps(shifted, round);
  const __m512i ki = _mm512_sub_epi32(_mm512_castps_si512(shifted), _mm512_castps_si512(round));
  const __m512 f = _mm512_sub_ps(t, k);
  __m512 q = _mm512_set1_ps(1.281443634e-3f);
  q = _mm512_fmadd_ps(q, f, _mm512_set1_ps(9.656608105e-3f));
  q = _mm512_fmadd_ps(q, f, _mm512_set1_ps(5.551610515e-2f));
  q = _mm512_fmadd_ps(q, f, _mm512_set1_ps(2.402247787e-1f));
  q = _mm512_fmadd_ps(q, f, _mm512_set1_ps(6.931468248e-1f));
  const __m512 one = _mm512_set1_ps(1.0f);
  const __m512 mantissa = _mm512_fmadd_ps(f, q, one);
  const __m512 power = _mm512_castsi512_ps(_mm512_slli_epi32(_mm512_add_epi32(ki, _mm512_set1_epi32(127)), 23));
  return _mm512_div_ps(one, _mm512_fmadd_ps(mantissa, power, one));
}

// J units of one layer for 16 V rows, sigmoid included: out[j] = S(bias + sum_k w[j][k] in[k]).
// With 32 registers the J V sums, the V inputs and a weight all stay in registers, and each
// sum goes through its sigmoid before it is stored (no pass of its own, as AVX2 needs).
template <int J, int V>
inline void layer_chunk(const Real* w, Index inputs, Real bias, const Real* in, Index in_ld, Real* out,
                        Index out_ld) {
  __m512 acc[J][V];
  #pragma GCC unroll 16
  for (int j = 0; j < J; ++j)
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) acc[j][v] = _mm512_set1_ps(bias);
  for (Index k = 0; k < inputs; ++k) {
    __m512 x[V];
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) x[v] = _mm512_loadu_ps(in + k * in_ld + 16 * v);
    #pragma GCC unroll 16
    for (int j = 0; j < J; ++j) {
      const __m512 wv = _mm512_set1_ps(w[j * inputs + k]);
      #pragma GCC unroll 16
      for (int v = 0; v < V; ++v) acc[j][v] = _mm512_fmadd_ps(wv, x[v], acc[j][v]);
    }
  }
  #pragma GCC unroll 16
  for (int j = 0; j < J; ++j)
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) _mm512_storeu_ps(out + j * out_ld + 16 * v, sigmoid16(acc[j][v]));
}

// Units in chunks of at most ten (20 sums for V = 2).
template <int V>
void layer(const Real* w, Index units, Index inputs, Real bias, const Real* in, Index in_ld, Real* out, Index out_ld) {
  constexpr Index kMaxChunk = 10;
  const Index chunks = (units + kMaxChunk - 1) / kMaxChunk;
  Index j0 = 0;
  for (Index c = 0; c < chunks; ++c) {
    const Index j1 = (c + 1) * units / chunks;
    const Real* wc = w + j0 * inputs;
    Real* oc = out + j0 * out_ld;
    switch (j1 - j0) {
      case 1: layer_chunk<1, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 2: layer_chunk<2, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 3: layer_chunk<3, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 4: layer_chunk<4, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 5: layer_chunk<5, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 6: layer_chunk<6, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 7: layer_chunk<7, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 8: layer_chunk<8, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      case 9: layer_chunk<9, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
      default: layer_chunk<10, V>(wc, inputs, bias, in, in_ld, oc, out_ld); break;
    }
    j0 = j1;
  }
}

// Both layers for 16 V rows of a network of H hidden units and T outputs, all in registers: each
// hidden sum goes through its sigmoid and straight into the T output sums (in hidden-unit
// order, as the definition adds them), so the output chains interleave with the sigmoids.
template <int H, int T, int V>
[[gnu::noinline]] void network_step_fused(const NetworkView& net, const Real* base_t, Index base_ld, Real* target_t, Index target_ld) {
  __m512 acc[H][V];
  #pragma GCC unroll 16
  for (int j = 0; j < H; ++j)
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) acc[j][v] = _mm512_set1_ps(net.b1);
  const Index inputs = net.inputs;
  for (Index k = 0; k < inputs; ++k) {
    __m512 x[V];
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) x[v] = _mm512_loadu_ps(base_t + k * base_ld + 16 * v);
    #pragma GCC unroll 16
    for (int j = 0; j < H; ++j) {
      const __m512 wv = _mm512_set1_ps(net.w1[j * inputs + k]);
      #pragma GCC unroll 16
      for (int v = 0; v < V; ++v) acc[j][v] = _mm512_fmadd_ps(wv, x[v], acc[j][v]);
    }
  }
  __m512 out[T][V];
  #pragma GCC unroll 16
  for (int t = 0; t < T; ++t)
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) out[t][v] = _mm512_set1_ps(net.b2);
  #pragma GCC unroll 16
  for (int j = 0; j < H; ++j)
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) {
      const __m512 h = sigmoid16(acc[j][v]);
      #pragma GCC unroll 16
      for (int t = 0; t < T; ++t) out[t][v] = _mm512_fmadd_ps(_mm512_set1_ps(net.w2[t * H + j]), h, out[t][v]);
    }
  #pragma GCC unroll 16
  for (int t = 0; t < T; ++t)
    #pragma GCC unroll 16
    for (int v = 0; v < V; ++v) _mm512_storeu_ps(target_t + t * target_ld + 16 * v, sigmoid16(out[t][v]));
}

// Both layers for 16 V rows, the hidden layer in `hidden` (units x 16 V, in L1): any shape.
template <int V>
void network_step(const NetworkView& net, const Real* base_t, Index base_ld, Real* hidden, Real* target_t,
                  Index target_ld) {
  if (net.hidden == 10 && net.outputs <= 4) {  // the paper's networks (10 hidden units, 2 or 4 outputs)
    switch (net.outputs) {
      case 1: return network_step_fused<10, 1, V>(net, base_t, base_ld, target_t, target_ld);
      case 2: return network_step_fused<10, 2, V>(net, base_t, base_ld, target_t, target_ld);
      case 3: return network_step_fused<10, 3, V>(net, base_t, base_ld, target_t, target_ld);
      default: return network_step_fused<10, 4, V>(net, base_t, base_ld, target_t, target_ld);
    }
  }
  layer<V>(net.w1, net.hidden, net.inputs, net.b1, base_t, base_ld, hidden, 16 * V);
  layer<V>(net.w2, net.outputs, net.hidden, net.b2, hidden, 16 * V, target_t, target_ld);
}

#elif defined(QDMETA_NETWORK_AVX2)

// base2_sigmoid() on eight lanes, operation for operation (the clamps as max/min with the
// constant first, so a NaN propagates as in the scalar ternaries).
inline __m256 sigmoid8(__m256 z) {
  __m256 t = _mm256_max_ps(_mm256_set1_ps(-125.0f), z);
  t = _mm256_min_ps(_mm256_set1_ps(125.0f), t);
  const __m256 round = _mm256_set1_ps(12582912.0f);
  const __m256 shifted = _mm256_add_ps(t, round);
  const __m256 k = _mm256_sub_ps(shifted, round);
  const __m256i ki = _mm256_sub_epi32(_mm256_castps_si256(shifted), _mm256_castps_si256(round));
  const __m256 f = _mm256_sub_ps(t, k);
  __m256 q = _mm256_set1_ps(1.281443634e-3f);
  q = _mm256_fmadd_ps(q, f, _mm256_set1_ps(9.656608105e-3f));
  q = _mm256_fmadd_ps(q, f, _mm256_set1_ps(5.551610515e-2f));
  q = _mm256_fmadd_ps(q, f, _mm256_set1_ps(2.402247787e-1f));
  q = _mm256_fmadd_ps(q, f, _mm256_set1_ps(6.931468248e-1f));
  const __m256 one = _mm256_set1_ps(1.0f);
  const __m256 mantissa = _mm256_fmadd_ps(f, q, one);
  const __m256 power = _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_add_epi32(ki, _mm256_set1_epi32(127)), 23));
  return _mm256_div_ps(one, _mm256_fmadd_ps(mantissa, power, one));
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
void layer16(const Real* w, Index units, Index inputs, Real bias, const Real* in, Index in_ld, Real* out,
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
  // The sigmoids in a pass of their own, the sums reloaded from L1: interleaved with the
  // accumulators they spilled registers (measured: this way the kernel is 20% faster).
  for (Index j = 0; j < units; ++j)
    for (Index r = 0; r < kKernelRows; r += 8)
      _mm256_storeu_ps(out + j * out_ld + r, sigmoid8(_mm256_loadu_ps(out + j * out_ld + r)));
}

#else

// Without AVX2 and FMA: the scalar definition, one row (column) at a time.
void layer_scalar(const Real* w, Index units, Index inputs, Real bias, const Real* in, Index in_ld,
                  Index count, Real* out, Index out_ld) {
  for (Index r = 0; r < count; ++r)
    for (Index j = 0; j < units; ++j) {
      Real acc = bias;
      for (Index k = 0; k < inputs; ++k) acc = fused(w[j * inputs + k], in[k * in_ld + r], acc);
      out[j * out_ld + r] = base2_sigmoid(acc);
    }
}

#endif

}  // namespace

void run_network_t(const NetworkView& net, const Real* base_t, Index base_ld, Index count, Real* target_t,
                   Index target_ld, BaseRows rows) {
  if (count <= 0) return;
  [[maybe_unused]] const bool streamed = rows == BaseRows::streamed;
#if defined(QDMETA_NETWORK_AVX512)
  // 32 rows per step (two vectors per unit), a last step of 16 when the padded count is odd.
  constexpr Index kStackHidden = 64;
  alignas(64) Real stack[kStackHidden * 2 * kKernelRows];
  std::vector<Real> heap;
  Real* hidden = stack;
  if (net.hidden > kStackHidden) {
    heap.resize(static_cast<std::size_t>(net.hidden * 2 * kKernelRows));
    hidden = heap.data();
  }
  const Index n = padded_rows(count);
  Index r = 0;
  for (; r + 2 * kKernelRows <= n; r += 2 * kKernelRows) {
    if (streamed) prefetch_ahead(base_t + r, base_ld, net.inputs, 2 * kKernelRows);
    network_step<2>(net, base_t + r, base_ld, hidden, target_t + r, target_ld);
  }
  for (; r < n; r += kKernelRows) network_step<1>(net, base_t + r, base_ld, hidden, target_t + r, target_ld);
#elif defined(QDMETA_NETWORK_AVX2)
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
    if (streamed) prefetch_ahead(base_t + r, base_ld, net.inputs, kKernelRows);
    layer16(net.w1, net.hidden, net.inputs, net.b1, base_t + r, base_ld, hidden, kKernelRows);
    layer16(net.w2, net.outputs, net.hidden, net.b2, hidden, kKernelRows, target_t + r, target_ld);
  }
#else
  const Index n = padded_rows(count);
  std::vector<Real> hidden(static_cast<std::size_t>(net.hidden * n));
  layer_scalar(net.w1, net.hidden, net.inputs, net.b1, base_t, base_ld, n, hidden.data(), n);
  layer_scalar(net.w2, net.outputs, net.hidden, net.b2, hidden.data(), n, n, target_t, target_ld);
#endif
}

}  // namespace qdmeta
