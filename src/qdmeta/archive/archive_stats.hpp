#pragma once
// Archive statistics with pyribs's names and meanings, computed one way for every archive.
#include <algorithm>
#include <limits>
#include <span>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct ArchiveStats {
  Index num_elites = 0;        // filled cells
  double coverage = 0.0;       // num_elites / cells, in [0, 1]
  double qd_score = 0.0;       // sum over elites of (objective - qd_offset)
  double norm_qd_score = 0.0;  // qd_score / cells
  double obj_max = 0.0;        // best objective (0 when empty)
  double obj_mean = 0.0;       // mean objective (0 when empty)
  bool operator==(const ArchiveStats&) const = default;
};

// The statistics of the elites that for_each_objective(visit) visits (visit(double) once per
// elite; the sum runs in that order, in double), over `capacity` cells: coverage and the
// normalised QD-score divide by it (coverage capped at 1, for containers that only steer toward
// a size, as AURORA's).
template <class ForEachObjective>
ArchiveStats archive_stats(ForEachObjective&& for_each_objective, double capacity, double qd_offset) {
  ArchiveStats s;
  double sum = 0.0;
  double best = -std::numeric_limits<double>::infinity();
  for_each_objective([&](double f) {
    ++s.num_elites;
    sum += f;
    best = std::max(best, f);
  });
  s.coverage = std::min(1.0, static_cast<double>(s.num_elites) / capacity);
  if (s.num_elites == 0) return s;
  s.obj_max = best;
  s.obj_mean = sum / static_cast<double>(s.num_elites);
  s.qd_score = sum - qd_offset * static_cast<double>(s.num_elites);
  s.norm_qd_score = s.qd_score / capacity;
  return s;
}

// Mean and standard error (sample SD / sqrt(n); 0 for n = 1) of one statistic over the maps of
// a meta-population.
struct MeanSe {
  double mean = 0.0;
  double se = 0.0;
  bool operator==(const MeanSe&) const = default;
};

// The archive statistics of every map of a meta-generation, summarised over the maps: the
// paper's figures aggregate "across the different archives within the meta-population".
struct PopulationStats {
  MeanSe num_elites;
  MeanSe obj_mean;
  MeanSe obj_max;
  MeanSe qd_score;
  bool operator==(const PopulationStats&) const = default;
};

// The summary of `archives` (at least one), each statistic's sum in the given order.
PopulationStats population_stats(std::span<const ArchiveStats> archives);

}  // namespace qdmeta
