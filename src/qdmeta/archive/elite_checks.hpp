#pragma once
// The one value check of an archive restored from bytes (a checkpoint, a pickle): what a run
// writes and adapt would accept in archive.csv. Objectives and measures need none here: the
// elite store refuses non-finite ones as it reads its cells back.
#include <string_view>

#include "qdmeta/archive/elite_table.hpp"

namespace qdmeta {

// Throws InputError "<what> is damaged: elite i (cell c) has a gene v, where every gene must lie
// in [0, 1]" for the first gene outside [0, 1] (or NaN), and likewise for a stored base feature
// outside [-1, 1] (QD-Meta's authors-2g-1 database inputs store 2g - 1).
void check_restored_elites(const EliteTable& elites, std::string_view what);

}  // namespace qdmeta
