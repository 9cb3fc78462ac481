#include "archive_pickle.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "numpy_arrays.hpp"
#include "pickled_state.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// Of the state tuples below; 2: with their checksum; 3: a grid's ranges; 4: thresholds.
constexpr int kArchiveStateFormat = 4;

const char* class_name(const GridArchive*) { return "GridArchive"; }
const char* class_name(const CvtArchive*) { return "CvtArchive"; }
const char* class_name(const UnstructuredArchive*) { return "UnstructuredArchive"; }

template <class Archive>
const std::string& who() {
  static const std::string name =
      fmt::format("unpickling a qdmeta.{}", class_name(static_cast<const Archive*>(nullptr)));
  return name;
}

// (format, parameters, seed, sample calls, the archive's checkpoint bytes, their checksum).
template <class Archive>
py::tuple state(const ArchiveHandle<Archive>& h, py::tuple parameters) {
  BinaryWriter out;
  h.archive.save(out);
  const py::int_ format(kArchiveStateFormat), seed(h.seed), calls(h.sample_calls);
  const py::bytes bytes(out.bytes());
  const py::int_ checksum(state_checksum({format, parameters, seed, calls, bytes}));
  return py::make_tuple(format, parameters, seed, calls, bytes, checksum);
}

// The parameters of a state made by state(), after its format and length are checked.
template <class Archive>
py::tuple parameters_of(const py::tuple& s, std::size_t count) {
  if (s.size() < 1 || !py::isinstance<py::int_>(s[0]))
    throw InputError(fmt::format("{}: the state is not one qdmeta made", who<Archive>()));
  if (!py::reinterpret_borrow<py::object>(s[0]).equal(py::int_(kArchiveStateFormat)))
    throw InputError(fmt::format("{}: state format {}, but this qdmeta reads format {}", who<Archive>(),
                                 py::str(s[0]).cast<std::string>(), kArchiveStateFormat));
  if (s.size() != 6 || !py::isinstance<py::tuple>(s[1]) || !py::isinstance<py::int_>(s[2]) ||
      !py::isinstance<py::int_>(s[3]) || !py::isinstance<py::bytes>(s[4]))
    throw InputError(fmt::format("{}: the state is not one qdmeta made", who<Archive>()));
  const py::tuple p = s[1];
  if (p.size() != count) throw InputError(fmt::format("{}: the state is not one qdmeta made", who<Archive>()));
  return p;
}

// The archive loaded (its load refuses a non-finite objective or measure), then its checksum.
template <class Archive>
ArchiveHandle<Archive> restored(Archive archive, const py::tuple& s) {
  const std::string bytes = s[4].cast<std::string>();
  BinaryReader in(bytes, fmt::format("the pickled {}", class_name(static_cast<const Archive*>(nullptr))));
  archive.load(in);
  in.finish();
  check_state_checksum(s[5], state_checksum({s[0], s[1], s[2], s[3], s[4]}), who<Archive>());
  return ArchiveHandle<Archive>(std::move(archive), s[2].cast<std::uint64_t>(), s[3].cast<std::uint64_t>());
}

// The restored archive with its pickled learning_rate and threshold_min (checked as given).
template <class Archive>
ArchiveHandle<Archive> with_thresholds(ArchiveHandle<Archive> h, py::handle learning_rate, py::handle threshold_min) {
  h.thresholds = threshold_arguments(learning_rate, threshold_min.cast<double>());
  return h;
}

}  // namespace

py::tuple archive_state(const ArchiveHandle<GridArchive>& h) {
  const GridArchiveParams& p = h.archive.params();
  return state(h, py::make_tuple(p.bins, p.lower, p.upper, p.solution_size, p.base_feature_size, p.qd_offset,
                                 p.epsilon, p.lower_bounds, p.upper_bounds, h.thresholds.alpha,
                                 h.thresholds.threshold_min));
}

template <>
ArchiveHandle<GridArchive> archive_from_state(const py::tuple& s) {
  const py::tuple v = parameters_of<GridArchive>(s, 11);
  GridArchiveParams p;
  p.bins = v[0].cast<std::vector<int>>();
  p.lower = v[1].cast<double>();
  p.upper = v[2].cast<double>();
  p.solution_size = v[3].cast<Index>();
  p.base_feature_size = v[4].cast<Index>();
  p.qd_offset = v[5].cast<double>();
  p.epsilon = v[6].cast<double>();
  p.lower_bounds = v[7].cast<std::vector<double>>();
  p.upper_bounds = v[8].cast<std::vector<double>>();
  p.validate();
  return with_thresholds(restored(GridArchive(p), s), v[9], v[10]);
}

py::tuple archive_state(const ArchiveHandle<CvtArchive>& h) {
  const CvtArchiveParams& p = h.archive.params();
  const RowMatrix& c = h.archive.centroids();
  return state(h, py::make_tuple(p.solution_size, p.qd_offset, p.neighbours, rows_copy(c.data(), c.rows(), c.cols()),
                                 h.thresholds.alpha, h.thresholds.threshold_min));
}

template <>
ArchiveHandle<CvtArchive> archive_from_state(const py::tuple& s) {
  const py::tuple v = parameters_of<CvtArchive>(s, 6);
  const CvtArchiveParams p{v[0].cast<Index>(), v[1].cast<double>(), v[2].cast<Index>()};
  const py::array raw = py::array::ensure(v[3]);
  if (!raw || raw.ndim() != 2) throw InputError("unpickling a qdmeta.CvtArchive: the state is not one qdmeta made");
  const FloatArray c = float_rows(raw, raw.shape(0), raw.shape(1), "centroids");
  return with_thresholds(
      restored(CvtArchive(p, RowMatrix(Eigen::Map<const RowMatrix>(c.data(), c.shape(0), c.shape(1)))), s), v[4], v[5]);
}

py::tuple archive_state(const ArchiveHandle<UnstructuredArchive>& h) {
  const UnstructuredArchiveParams& p = h.archive.params();
  return state(h, py::make_tuple(p.measure_size, p.solution_size, p.base_feature_size, p.target_size, p.eps,
                                 p.novelty_neighbours, p.qd_offset));
}

template <>
ArchiveHandle<UnstructuredArchive> archive_from_state(const py::tuple& s) {
  const py::tuple v = parameters_of<UnstructuredArchive>(s, 7);
  UnstructuredArchiveParams p;
  p.measure_size = v[0].cast<Index>();
  p.solution_size = v[1].cast<Index>();
  p.base_feature_size = v[2].cast<Index>();
  p.target_size = v[3].cast<Index>();
  p.eps = v[4].cast<double>();
  p.novelty_neighbours = v[5].cast<int>();
  p.qd_offset = v[6].cast<double>();
  p.validate();
  return restored(UnstructuredArchive(p), s);
}

}  // namespace qdmeta::python
