#pragma once
// Pickling the Python archives: a tuple of a format number, the archive's parameters, its
// sample_elites() stream (seed, calls) and the archive's own checkpoint bytes (save()), so an
// unpickled archive is the original: the same elites in the same fill order, cells, statistics
// and future samples.
#include <pybind11/pybind11.h>

#include "archive_handle.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/archive/unstructured_archive.hpp"

namespace qdmeta::python {

pybind11::tuple archive_state(const ArchiveHandle<GridArchive>& handle);
pybind11::tuple archive_state(const ArchiveHandle<CvtArchive>& handle);
pybind11::tuple archive_state(const ArchiveHandle<UnstructuredArchive>& handle);

// The archive back from archive_state()'s tuple; an InputError when `state` is not one it made.
template <class Archive>
ArchiveHandle<Archive> archive_from_state(const pybind11::tuple& state);
template <>
ArchiveHandle<GridArchive> archive_from_state(const pybind11::tuple& state);
template <>
ArchiveHandle<CvtArchive> archive_from_state(const pybind11::tuple& state);
template <>
ArchiveHandle<UnstructuredArchive> archive_from_state(const pybind11::tuple& state);

}  // namespace qdmeta::python
