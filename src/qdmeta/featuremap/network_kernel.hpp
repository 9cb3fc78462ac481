#pragma once
// The feature-map network's inner loop over a transposed block (features across rows of memory,
// database rows across SIMD lanes): both layers and both sigmoids for kKernelRows rows at a time,
// the hidden layer never leaving registers and the L1 cache. Every row goes through the same
// float operations, in the same order, as the scalar definition in neural_feature_map.hpp
// (fused multiply-adds from the bias in input order, then base2_sigmoid), so lanes, the scalar
// fallback and any block size give the same bits.
#include "qdmeta/core/types.hpp"

namespace qdmeta {

// Rows per kernel step: two 8-lane AVX vectors, so each weight broadcast feeds two products.
inline constexpr Index kKernelRows = 16;
inline constexpr Index padded_rows(Index count) { return (count + kKernelRows - 1) / kKernelRows * kKernelRows; }

// The network's weights as NeuralFeatureMap keeps them (float, row-major, each layer's already
// multiplied by its sigmoid's -alpha log2(e) / (N + 1)).
struct NetworkView {
  const Real* w1 = nullptr;  // hidden x inputs
  const Real* w2 = nullptr;  // outputs x hidden
  Index inputs = 0;
  Index hidden = 0;
  Index outputs = 0;
  Real b1 = 0;
  Real b2 = 0;
};

// Where base_t's rows are when the network reads them: `cached` when an earlier pass brought them
// into the caches (a rebuild's later maps over a chunk), `streamed` when they come from memory (its
// first map, every map when lambda = 1). Streamed rows are asked for ahead of the kernel: one
// stream per base feature is more than the hardware prefetcher follows, and the kernel then
// waited on memory. Only the speed depends on it, never a bit of the result.
enum class BaseRows { cached, streamed };

// target_t (outputs x target_ld) = the network over base_t (inputs x base_ld), row-major, for
// columns [0, padded_rows(count)): both leading dimensions must be at least that, the padding
// columns of base_t are read (keep them finite, e.g. zero) and those of target_t are written.
void run_network_t(const NetworkView& net, const Real* base_t, Index base_ld, Index count, Real* target_t,
                   Index target_ld, BaseRows rows = BaseRows::cached);

}  // namespace qdmeta
