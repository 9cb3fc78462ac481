#pragma once
// Archive statistics with pyribs's names and meanings.
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

}  // namespace qdmeta
