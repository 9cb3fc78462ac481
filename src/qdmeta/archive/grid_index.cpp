// GCC 12's avx512fintrin.h passes _mm512_undefined_pd() as the masked-off source of max, min and
// conversions and then warns about it at every use (fixed in GCC 13): the pragma must come
// before the first include, which pulls the header in.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13 && defined(__AVX512F__)
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include "qdmeta/archive/grid_index.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/fused.hpp"

#if defined(__AVX512F__)
#include <immintrin.h>
#define QDMETA_GRID_INDEX_AVX512 1
#elif defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define QDMETA_GRID_INDEX_AVX2 1
#endif

namespace qdmeta {

GridIndex::GridIndex(const GridArchiveParams& params)
{
  const auto dims = params.bins.size();
  for (std::size_t d = 0; d < dims; ++d) {
    lower_.push_back(params.lower_of(d));
    scale_.push_back(1.0 / (params.upper_of(d) - params.lower_of(d)));
  }
  bins_.resize(dims);
  top_.resize(dims);
  margin_.resize(dims);
  stride_.assign(dims, 1);
  std::int32_t stride = 1;
  for (std::size_t d = dims; d-- > 0;) {
    const double b = params.bins[d];
    bins_[d] = b;
    top_[d] = b - 1;
    // Measures are floats, rounded by up to half a float ulp (6e-8 relative): scaled by the
    // bin count that can exceed epsilon, so the margin grows with the bins.
    margin_[d] = fused(b, static_cast<double>(std::numeric_limits<float>::epsilon()), params.epsilon);
    stride_[d] = stride;
    stride *= params.bins[d];
  }
}

Index GridIndex::cell_of(const Real* measures) const {
  Index cell = 0;
  for (std::size_t d = 0; d < bins_.size(); ++d) {
    const double m = measures[d];
    if (std::isnan(m)) throw Error(fmt::format("grid archive: target feature {} is NaN", d));
    const double pos = std::floor(fused((m - lower_[d]) * scale_[d], bins_[d], margin_[d]));
    cell += static_cast<Index>(std::clamp(pos, 0.0, top_[d])) * stride_[d];
  }
  return cell;
}

void GridIndex::cells_of_t(const Real* measures_t, Index ld, Index count, std::int32_t* cells) const {
  const auto dims = static_cast<Index>(bins_.size());
  Index r = 0;
#if defined(QDMETA_GRID_INDEX_AVX512)
  // Sixteen rows per step in two halves of eight double lanes.
  const __m512d zero = _mm512_setzero_pd();
  for (; r + 16 <= count; r += 16) {
    __m256i lo = _mm256_setzero_si256(), hi = _mm256_setzero_si256();
    __mmask16 nan = 0;
    for (Index d = 0; d < dims; ++d) {
      const auto du = static_cast<std::size_t>(d);
      const __m512 m = _mm512_loadu_ps(measures_t + d * ld + r);
      nan |= _mm512_cmp_ps_mask(m, m, _CMP_UNORD_Q);
      const __m512d bins = _mm512_set1_pd(bins_[du]), margin = _mm512_set1_pd(margin_[du]);
      const __m512d lower = _mm512_set1_pd(lower_[du]), scale = _mm512_set1_pd(scale_[du]);
      const __m512d top = _mm512_set1_pd(top_[du]);
      const __m256i stride = _mm256_set1_epi32(stride_[du]);
      auto half = [&](__m256 m8) {
        const __m512d x = _mm512_mul_pd(_mm512_sub_pd(_mm512_cvtps_pd(m8), lower), scale);
        const __m512d pos = _mm512_roundscale_pd(_mm512_fmadd_pd(x, bins, margin), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
        const __m512d clamped = _mm512_min_pd(_mm512_max_pd(pos, zero), top);
        return _mm256_mullo_epi32(_mm512_cvttpd_epi32(clamped), stride);
      };
      lo = _mm256_add_epi32(lo, half(_mm512_castps512_ps256(m)));
      hi = _mm256_add_epi32(hi, half(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(m), 1))));
    }
    if (nan) break;  // the scalar loop below throws with the dimension's name
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(cells + r), lo);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(cells + r + 8), hi);
  }
#elif defined(QDMETA_GRID_INDEX_AVX2)
  const __m256d zero = _mm256_setzero_pd();
  for (; r + 8 <= count; r += 8) {
    __m128i lo = _mm_setzero_si128(), hi = _mm_setzero_si128();
    bool nan = false;
    for (Index d = 0; d < dims; ++d) {
      const auto du = static_cast<std::size_t>(d);
      const __m256 m = _mm256_loadu_ps(measures_t + d * ld + r);
      nan |= _mm256_movemask_ps(_mm256_cmp_ps(m, m, _CMP_UNORD_Q)) != 0;
      const __m256d bins = _mm256_set1_pd(bins_[du]), margin = _mm256_set1_pd(margin_[du]);
      const __m256d lower = _mm256_set1_pd(lower_[du]), scale = _mm256_set1_pd(scale_[du]);
      const __m256d top = _mm256_set1_pd(top_[du]);
      const __m128i stride = _mm_set1_epi32(stride_[du]);
      auto half = [&](__m128 m4) {
        const __m256d x = _mm256_mul_pd(_mm256_sub_pd(_mm256_cvtps_pd(m4), lower), scale);
        const __m256d pos = _mm256_round_pd(_mm256_fmadd_pd(x, bins, margin), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
        const __m256d clamped = _mm256_min_pd(_mm256_max_pd(pos, zero), top);
        return _mm_mullo_epi32(_mm256_cvttpd_epi32(clamped), stride);
      };
      lo = _mm_add_epi32(lo, half(_mm256_castps256_ps128(m)));
      hi = _mm_add_epi32(hi, half(_mm256_extractf128_ps(m, 1)));
    }
    if (nan) break;  // the scalar loop below throws with the dimension's name
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cells + r), lo);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cells + r + 4), hi);
  }
#endif
  // The rows left over (all of them without AVX2), gathered into one vector each.
  std::vector<Real> row(static_cast<std::size_t>(dims));
  for (; r < count; ++r) {
    for (Index d = 0; d < dims; ++d) row[static_cast<std::size_t>(d)] = measures_t[d * ld + r];
    cells[r] = static_cast<std::int32_t>(cell_of(row.data()));
  }
}

}  // namespace qdmeta
