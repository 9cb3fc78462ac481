#include "qdmeta/archive/centroid_values.hpp"

#include <algorithm>
#include <cstring>

namespace qdmeta {
namespace {

// 16 floats: one AVX-512 register, split by the compiler into narrower ones on other machines.
using Lanes = Real __attribute__((vector_size(16 * sizeof(Real))));
constexpr Index kLanes = kValueLanes;

// Through a reference: a vector returned by value changes the ABI where 512-bit registers are
// missing (GCC's -Wpsabi).
void load(Lanes& v, const Real* p) { std::memcpy(&v, p, sizeof v); }

// R points x C blocks of 16 centroids, all accumulators in registers; at least 8 independent
// accumulators keep both multiply-add pipes busy (R * C >= 8).
template <int R, int C>
void kernel(const Real* points, const Real* blocked, const Real* norms, Index k, Index d, Real* values) {
  const Index block_floats = d * kLanes;
  for (Index j = 0; j < k; j += C * kLanes) {
    const Index chunks = std::min<Index>(C, (k - j) / kLanes);
    Lanes acc[R][C];
    for (int c = 0; c < C; ++c)
      for (int r = 0; r < R; ++r) {
        acc[r][c] = Lanes{};
        if (c < chunks) load(acc[r][c], norms + j + c * kLanes);
      }
    const Real* t = blocked + (j / kLanes) * block_floats;
    for (Index i = 0; i < d; ++i)
      for (int c = 0; c < C; ++c) {
        if (c >= chunks) break;
        Lanes column;
        load(column, t + c * block_floats + i * kLanes);
        for (int r = 0; r < R; ++r) acc[r][c] += points[r * d + i] * column;
      }
    for (int r = 0; r < R; ++r)
      for (int c = 0; c < chunks; ++c) std::memcpy(values + r * k + j + c * kLanes, &acc[r][c], sizeof(Lanes));
  }
}

}  // namespace

void centroid_values(const Real* points, Index rows, const Real* blocked, const Real* norms, Index k, Index d,
                     Real* values) {
  switch (rows) {
    case 1: return kernel<1, 8>(points, blocked, norms, k, d, values);
    case 2: return kernel<2, 4>(points, blocked, norms, k, d, values);
    case 3: return kernel<3, 3>(points, blocked, norms, k, d, values);
    case 4: return kernel<4, 2>(points, blocked, norms, k, d, values);
    case 5: return kernel<5, 2>(points, blocked, norms, k, d, values);
    case 6: return kernel<6, 2>(points, blocked, norms, k, d, values);
    case 7: return kernel<7, 2>(points, blocked, norms, k, d, values);
    default: return kernel<8, 1>(points, blocked, norms, k, d, values);
  }
}

}  // namespace qdmeta
