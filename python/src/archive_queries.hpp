#pragma once
// What a pyribs user asks of an archive besides add(), for GridArchive, CvtArchive and
// UnstructuredArchive alike (and for the archive an Algorithm runs):
//   retrieve(measures)        -> (occupied (n,) bool, {index, objective, measures, solution
//                                [, base_features]}): the elite of each row's cell (the
//                                unstructured archive: the member nearest the row); a row
//                                with no elite has index -1 and NaN everywhere else, as in pyribs;
//   retrieve_single(measures) -> (occupied, {...}) for one measure vector;
//   sample_elites(n, replace) -> {...}: n elites drawn uniformly from the archive's members;
//   iteration                 -> one dict per elite, in cell order, from a snapshot.
#include <pybind11/pybind11.h>

#include "numpy_arrays.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/elite_table.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/archive/unstructured_archive.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta::python {

// `measures` as rows (rows < 0: any count) of `dimensions` finite values; an InputError names
// the first value that is not finite.
FloatArray measure_rows(pybind11::handle measures, Index rows, Index dimensions);

template <class Archive>
pybind11::tuple retrieve(const Archive& archive, pybind11::handle measures);
template <class Archive>
pybind11::tuple retrieve_single(const Archive& archive, pybind11::handle measures);
// n >= 0; an empty archive, or n above its size without replacement, is an InputError.
template <class Archive>
pybind11::dict sample_elites(const Archive& archive, Rng rng, Index n, bool replace);

// The unstructured archive's members as an elite table (index = slot).
EliteTable member_table(const UnstructuredArchive& archive);

// An iterator over a snapshot of `table`'s elites, one dict per row.
pybind11::object iterate_elites(EliteTable table);
// The iterator's class (qdmeta.EliteIterator).
void bind_elite_iterator(pybind11::module_& m);

}  // namespace qdmeta::python
