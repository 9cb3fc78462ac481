#pragma once
// The archive an Algorithm runs, for Python: MAP-Elites's grid, CVT-MAP-Elites's CVT archive
// (with its centroids, made first when no step has made them yet), AURORA's unstructured
// archive (measures: its z-scored latent codes), and QD-Meta's best map's grid of the latest
// meta-generation (measures: that map's target features), the archive its stats and data()
// describe. Another algorithm is a qdmeta.Error.
#include <pybind11/pybind11.h>

#include <cstdint>

#include "qdmeta/algorithms/algorithm.hpp"

namespace qdmeta::python {

// A copy, as a qdmeta.GridArchive, CvtArchive or UnstructuredArchive whose sample_elites()
// streams are seeded with `seed`.
pybind11::object archive_copy(Algorithm& algorithm, std::uint64_t seed);
// retrieve(measures) on that archive itself (no copy).
pybind11::tuple retrieve_from(Algorithm& algorithm, pybind11::handle measures);

}  // namespace qdmeta::python
