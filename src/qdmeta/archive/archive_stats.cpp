#include "qdmeta/archive/archive_stats.hpp"

#include <cmath>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

namespace {

// Two passes in the archives' order; the squares are fused explicitly so that the last digit does
// not depend on whether the compiler contracts them for the CPU it tunes for.
template <class Field>
MeanSe mean_se(std::span<const ArchiveStats> archives, Field field) {
  const auto n = static_cast<double>(archives.size());
  double sum = 0.0;
  for (const ArchiveStats& s : archives) sum += field(s);
  MeanSe out;
  out.mean = sum / n;
  if (archives.size() < 2) return out;
  double squares = 0.0;
  for (const ArchiveStats& s : archives) {
    const double d = field(s) - out.mean;
    squares = std::fma(d, d, squares);
  }
  out.se = std::sqrt(squares / (n - 1.0)) / std::sqrt(n);
  return out;
}

}  // namespace

PopulationStats population_stats(std::span<const ArchiveStats> archives) {
  if (archives.empty()) throw Error("population_stats: no archives");
  PopulationStats p;
  p.num_elites = mean_se(archives, [](const ArchiveStats& s) { return static_cast<double>(s.num_elites); });
  p.obj_mean = mean_se(archives, [](const ArchiveStats& s) { return s.obj_mean; });
  p.obj_max = mean_se(archives, [](const ArchiveStats& s) { return s.obj_max; });
  p.qd_score = mean_se(archives, [](const ArchiveStats& s) { return s.qd_score; });
  return p;
}

}  // namespace qdmeta
