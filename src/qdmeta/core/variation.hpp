#pragma once
// A variation operator of the caller's: a registered `[mutation] kind` (plugin/part_registries.hpp),
// a part handed to build_run, or the Python module's `variation=`. It fills `offspring` (rows
// already sized) from rows r of `parents` and `partners`, two elites per offspring, and `seed`, a
// number for its own generator; every gene it writes must be in [0, 1]. Any algorithm whose
// Mutation carries one (MutationParams::variation) makes all its offspring with it.
#include <cstdint>
#include <functional>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

using VariationFunction = std::function<void(const RowMatrix& parents, const RowMatrix& partners, std::uint64_t seed,
                                             RowMatrix& offspring)>;

}  // namespace qdmeta
