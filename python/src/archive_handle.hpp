#pragma once
// An archive as Python holds it: the archive, the random streams of its sample_elites() and
// CMA-MAE's threshold params (pyribs's learning_rate and threshold_min; a Scheduler keeps the
// per-cell thresholds themselves). Call k of sample_elites() draws from the stream (seed, k), so
// a copy or an unpickled archive samples exactly as the original would have from there on.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/emitters/cell_thresholds.hpp"

namespace qdmeta::python {

inline constexpr std::uint64_t kDefaultArchiveSeed = 1;  // the config's default seed
// The purpose key of sample_elites()'s streams ("SAMPLE"): far above the library's StreamKey
// values (rng.hpp), so the draws never share a stream with an algorithm of the same seed.
inline constexpr std::uint64_t kSampleElitesStream = 0x53414D504C45;

template <class Archive>
struct ArchiveHandle {
  explicit ArchiveHandle(Archive a, std::uint64_t s = kDefaultArchiveSeed, std::uint64_t calls = 0)
      : archive(std::move(a)), seed(s), sample_calls(calls) {}

  // The stream of the next sample_elites() call.
  Rng next_sample_stream() { return Rng::stream(seed, {kSampleElitesStream, sample_calls++}); }

  Archive archive;
  std::uint64_t seed;
  std::uint64_t sample_calls;  // sample_elites() calls so far
  ThresholdParams thresholds;  // alpha = 1, threshold_min = -inf (CMA-ME) unless given
};

// A seed argument: any Python integer (numpy's too) in [0, 2^63 - 1], else a one-line error naming it.
std::uint64_t seed_argument(pybind11::handle value);

// learning_rate (pyribs's name for CMA-MAE's alpha; None is 1) and threshold_min checked, with
// errors naming the argument.
ThresholdParams threshold_arguments(pybind11::handle learning_rate, double threshold_min);

// A grid's bound of each measure (pyribs's lower_bounds / upper_bounds).
inline std::vector<double> bounds_of(const GridArchiveParams& p, bool upper) {
  std::vector<double> out;
  for (std::size_t d = 0; d < p.bins.size(); ++d) out.push_back(upper ? p.upper_of(d) : p.lower_of(d));
  return out;
}

// GridArchive.lower / .upper: the one bound every measure shares; a grid made with ranges= of
// differing bounds has none, and says which property to read instead.
inline double common_bound(const GridArchiveParams& p, bool upper) {
  const std::vector<double> all = bounds_of(p, upper);
  for (double b : all) {
    if (b != all.front()) {
      throw pybind11::value_error(upper ? "GridArchive.upper: the measures have different ranges; read upper_bounds"
                                        : "GridArchive.lower: the measures have different ranges; read lower_bounds");
    }
  }
  return all.empty() ? (upper ? p.upper : p.lower) : all.front();
}

}  // namespace qdmeta::python
