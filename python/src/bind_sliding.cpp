// qdmeta.SlidingBoundariesArchive: Fontaine et al.'s sliding-boundaries grid, with pyribs's
// SlidingBoundariesArchive's names, arguments and add() result.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "double_arrays.hpp"
#include "pickled_state.hpp"
#include "qdmeta/archive/sliding_boundaries_archive.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

py::dict elite_data(const SlidingBoundariesArchive& a) {
  const auto cells = a.elite_cells();
  const auto s = a.params().solution_size;
  const auto m = a.measure_size();
  std::vector<double> solutions, objectives, measures;
  std::vector<std::int32_t> index;
  for (Index cell : cells) {
    const auto x = a.solution(cell);
    const auto at = a.measures(cell);
    solutions.insert(solutions.end(), x.begin(), x.end());
    measures.insert(measures.end(), at.begin(), at.end());
    objectives.push_back(a.objective(cell));
    index.push_back(static_cast<std::int32_t>(cell));
  }
  py::dict all;
  all["solution"] = matrix_array(solutions, s);
  all["objective"] = vector_array(objectives);
  all["measures"] = matrix_array(measures, m);
  all["index"] = vector_array(index);
  return all;
}

SlidingBoundariesArchive make_sliding(Index solution_dim, std::vector<Index> dims,
                                      std::vector<std::pair<double, double>> ranges, double epsilon,
                                      double qd_score_offset, Index remap_frequency, Index buffer_capacity) {
  SlidingBoundariesParams p;
  p.solution_size = solution_dim;
  p.dims = std::move(dims);
  for (const auto& [lower, upper] : ranges) {
    p.lower_bounds.push_back(lower);
    p.upper_bounds.push_back(upper);
  }
  p.epsilon = epsilon;
  p.qd_offset = qd_score_offset;
  p.remap_frequency = remap_frequency;
  p.buffer_capacity = buffer_capacity;
  return SlidingBoundariesArchive(p);
}

constexpr int kSlidingStateFormat = 1;  // of the pickled state tuple

// (format, the constructor's arguments, the archive's checkpoint, checksum): an unpickled
// archive adds and remaps to the same bits as the original.
py::tuple sliding_state(const SlidingBoundariesArchive& a) {
  const SlidingBoundariesParams& p = a.params();
  py::list ranges;
  for (std::size_t i = 0; i < p.dims.size(); ++i) ranges.append(py::make_tuple(p.lower_bounds[i], p.upper_bounds[i]));
  BinaryWriter out;
  a.save(out);
  const py::int_ format(kSlidingStateFormat);
  const py::tuple params = py::make_tuple(p.solution_size, py::cast(p.dims), ranges, p.epsilon, p.qd_offset,
                                          p.remap_frequency, p.buffer_capacity);
  const py::bytes bytes(out.bytes());
  return py::make_tuple(format, params, bytes, py::int_(state_checksum({format, params, bytes})));
}

SlidingBoundariesArchive sliding_from_state(const py::tuple& s) {
  const char* who = "unpickling a qdmeta.SlidingBoundariesArchive";
  if (s.size() != 4 || !py::reinterpret_borrow<py::object>(s[0]).equal(py::int_(kSlidingStateFormat)) ||
      !py::isinstance<py::tuple>(s[1]) || py::len(s[1]) != 7 || !py::isinstance<py::bytes>(s[2]))
    throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
  check_state_checksum(s[3], state_checksum({s[0], s[1], s[2]}), who);
  const auto p = s[1].cast<py::tuple>();
  SlidingBoundariesArchive a = make_sliding(p[0].cast<Index>(), p[1].cast<std::vector<Index>>(),
                                            p[2].cast<std::vector<std::pair<double, double>>>(), p[3].cast<double>(),
                                            p[4].cast<double>(), p[5].cast<Index>(), p[6].cast<Index>());
  const std::string bytes = s[2].cast<std::string>();
  BinaryReader in(bytes, "the pickled SlidingBoundariesArchive");
  a.load(in);
  in.finish();
  return a;
}

}  // namespace

void bind_sliding_boundaries_archive(py::module_& m) {
  py::class_<SlidingBoundariesArchive>(m, "SlidingBoundariesArchive", R"doc(
The sliding-boundaries archive (Fontaine et al. 2019), as pyribs's SlidingBoundariesArchive: a
grid whose boundaries start evenly spaced over `ranges` and, every remap_frequency solutions,
move to the quantiles of the measures of the last buffer_capacity solutions, the elites and the
buffer then added again. add() takes its rows one at a time, in order.)doc")
      .def(py::init(&make_sliding),
           py::kw_only(), py::arg("solution_dim"), py::arg("dims"), py::arg("ranges"), py::arg("epsilon") = 1e-6,
           py::arg("qd_score_offset") = 0.0, py::arg("remap_frequency") = 100, py::arg("buffer_capacity") = 1000)
      .def(
          "add",
          [](SlidingBoundariesArchive& a, py::handle solution, py::handle objective, py::handle measures) {
            const DoubleArray at = double_rows(measures, -1, a.measure_size(), "measures");
            const py::ssize_t n = at.shape(0);
            const DoubleArray x = double_rows(solution, n, a.params().solution_size, "solution");
            const DoubleArray f = double_rows(objective, n, -1, "objective");
            const SlidingAddResult r = a.add(values(x), values(f), values(at));
            py::dict out;
            out["status"] = vector_array(std::vector<std::int32_t>(r.status.begin(), r.status.end()));
            out["value"] = vector_array(r.value);
            return out;
          },
          py::arg("solution"), py::arg("objective"), py::arg("measures"),
          "add(solution (n, solution_dim), objective (n,), measures (n, measure_dim)) -> {status, value}: pyribs's "
          "codes, 0 not added, 1 improved its cell, 2 a new cell; value the objective less the cell's before")
      .def(
          "index_of",
          [](const SlidingBoundariesArchive& a, py::handle measures) {
            const auto cells = a.index_of(values(double_rows(measures, -1, a.measure_size(), "measures")));
            return vector_array(std::vector<std::int32_t>(cells.begin(), cells.end()));
          },
          py::arg("measures"))
      .def(
          "data",
          [](const SlidingBoundariesArchive& a, std::optional<std::string> field) -> py::object {
            py::dict all = elite_data(a);
            if (!field) return all;
            if (!all.contains(*field))
              throw InputError("data(): unknown field '" + *field + "': use solution, objective, measures or index");
            return all[py::str(*field)];
          },
          py::arg("fields") = py::none(), "data() -> dict of arrays; data(field) -> that array (pyribs's names)")
      .def_property_readonly("boundaries",
                             [](const SlidingBoundariesArchive& a) {
                               py::list out;
                               for (Index i = 0; i < a.measure_size(); ++i) out.append(vector_array(a.boundaries(i)));
                               return out;
                             })
      .def("__len__", &SlidingBoundariesArchive::size)
      .def_property_readonly("empty", [](const SlidingBoundariesArchive& a) { return a.size() == 0; })
      .def_property_readonly("stats", &SlidingBoundariesArchive::stats)
      .def_property_readonly("cells", &SlidingBoundariesArchive::cells)
      .def_property_readonly("dims", [](const SlidingBoundariesArchive& a) { return a.params().dims; })
      .def_property_readonly("solution_dim", [](const SlidingBoundariesArchive& a) { return a.params().solution_size; })
      .def_property_readonly("measure_dim", &SlidingBoundariesArchive::measure_size)
      .def_property_readonly("remap_frequency",
                             [](const SlidingBoundariesArchive& a) { return a.params().remap_frequency; })
      .def_property_readonly("buffer_capacity",
                             [](const SlidingBoundariesArchive& a) { return a.params().buffer_capacity; })
      .def_property_readonly("qd_score_offset", [](const SlidingBoundariesArchive& a) { return a.params().qd_offset; })
      .def(py::pickle([](const SlidingBoundariesArchive& a) { return sliding_state(a); },
                      [](const py::tuple& s) { return sliding_from_state(s); }));
}

}  // namespace qdmeta::python
