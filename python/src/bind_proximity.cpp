// qdmeta.ProximityArchive: novelty search's archive, with pyribs's ProximityArchive's names,
// arguments and add() result.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "double_arrays.hpp"
#include "pickled_state.hpp"
#include "qdmeta/archive/proximity_archive.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

constexpr int kProximityStateFormat = 1;  // of the pickled state tuple

ProximityArchive make_proximity(Index solution_dim, Index measure_dim, Index k_neighbors, double novelty_threshold,
                                bool local_competition, double qd_score_offset,
                                std::optional<double> threshold_decay_rate, Index threshold_decay_itrs,
                                double threshold_decay_min) {
  ProximityArchiveParams p;
  p.solution_size = solution_dim;
  p.measure_size = measure_dim;
  p.k_neighbors = k_neighbors;
  p.novelty_threshold = novelty_threshold;
  p.local_competition = local_competition;
  p.qd_offset = qd_score_offset;
  p.threshold_decay_rate = threshold_decay_rate;
  p.threshold_decay_itrs = threshold_decay_itrs;
  p.threshold_decay_min = threshold_decay_min;
  return ProximityArchive(p);
}

// (format, the constructor's arguments, the archive's checkpoint, checksum): an unpickled
// archive adds, and decays its threshold, to the same bits as the original.
py::tuple proximity_state(const ProximityArchive& a) {
  const ProximityArchiveParams& p = a.params();
  BinaryWriter out;
  a.save(out);
  const py::int_ format(kProximityStateFormat);
  const py::tuple params = py::make_tuple(p.solution_size, p.measure_size, p.k_neighbors, p.novelty_threshold,
                                          p.local_competition, p.qd_offset, py::cast(p.threshold_decay_rate),
                                          p.threshold_decay_itrs, p.threshold_decay_min);
  const py::bytes bytes(out.bytes());
  return py::make_tuple(format, params, bytes, py::int_(state_checksum({format, params, bytes})));
}

ProximityArchive proximity_from_state(const py::tuple& s) {
  const char* who = "unpickling a qdmeta.ProximityArchive";
  if (s.size() != 4 || !py::reinterpret_borrow<py::object>(s[0]).equal(py::int_(kProximityStateFormat)) ||
      !py::isinstance<py::tuple>(s[1]) || py::len(s[1]) != 9 || !py::isinstance<py::bytes>(s[2]))
    throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
  check_state_checksum(s[3], state_checksum({s[0], s[1], s[2]}), who);
  const auto p = s[1].cast<py::tuple>();
  ProximityArchive a = make_proximity(p[0].cast<Index>(), p[1].cast<Index>(), p[2].cast<Index>(), p[3].cast<double>(),
                                      p[4].cast<bool>(), p[5].cast<double>(), p[6].cast<std::optional<double>>(),
                                      p[7].cast<Index>(), p[8].cast<double>());
  const std::string bytes = s[2].cast<std::string>();
  BinaryReader in(bytes, "the pickled ProximityArchive");
  a.load(in);
  in.finish();
  return a;
}

}  // namespace

void bind_proximity_archive(py::module_& m) {
  py::class_<ProximityArchive>(m, "ProximityArchive", R"doc(
Novelty search's archive, as pyribs's ProximityArchive: a solution whose novelty (mean
Euclidean distance to its k nearest elites, judged against the archive before the batch) is at
least novelty_threshold is added; with local_competition, one that is not replaces its nearest
elite when its objective is higher; with threshold_decay_rate, threshold_decay_itrs adds in a
row with nothing novel multiply the threshold by it, down to threshold_decay_min.)doc")
      .def(py::init(&make_proximity),
           py::kw_only(), py::arg("solution_dim"), py::arg("measure_dim"), py::arg("k_neighbors"),
           py::arg("novelty_threshold"), py::arg("local_competition") = false, py::arg("qd_score_offset") = 0.0,
           py::arg("threshold_decay_rate") = py::none(), py::arg("threshold_decay_itrs") = 1,
           py::arg("threshold_decay_min") = 0.0)
      .def(
          "add",
          [](ProximityArchive& a, py::handle solution, py::handle objective, py::handle measures) {
            const Index s = a.params().solution_size;
            const Index d = a.params().measure_size;
            if (objective.is_none() && a.params().local_competition)
              throw InputError("objective must be given when local_competition is on");
            const DoubleArray at = double_rows(measures, -1, d, "measures");
            const py::ssize_t n = at.shape(0);
            const DoubleArray x = double_rows(solution, n, s, "solution");
            DoubleArray f = objective.is_none() ? new_array<double, py::array::c_style | py::array::forcecast>({n})
                                                : double_rows(objective, n, -1, "objective");
            if (objective.is_none()) std::fill(f.mutable_data(), f.mutable_data() + n, 0.0);  // pyribs: objective 0
            const ProximityAddResult r = a.add(values(x), values(f), values(at));
            py::dict out;
            out["status"] = vector_array(std::vector<std::int32_t>(r.status.begin(), r.status.end()));
            out["novelty"] = vector_array(r.novelty);
            if (a.params().local_competition) {
              out["local_competition"] = vector_array(r.local_competition);
              out["value"] = vector_array(r.value);
            }
            return out;
          },
          py::arg("solution"), py::arg("objective"), py::arg("measures"),
          "add(solution (n, solution_dim), objective (n,) or None, measures (n, measure_dim)) -> {status, novelty[, "
          "local_competition, value]}: pyribs's codes, 0 not added, 1 replaced its nearest elite, 2 added as novel")
      .def(
          "compute_novelty",
          [](const ProximityArchive& a, py::handle measures) {
            return vector_array(a.novelty(values(double_rows(measures, -1, a.params().measure_size, "measures"))));
          },
          py::arg("measures"))
      .def(
          "index_of",
          [](const ProximityArchive& a, py::handle measures) {
            const auto nearest = a.index_of(values(double_rows(measures, -1, a.params().measure_size, "measures")));
            return vector_array(std::vector<std::int32_t>(nearest.begin(), nearest.end()));
          },
          py::arg("measures"))
      .def(
          "data",
          [](const ProximityArchive& a, std::optional<std::string> field) -> py::object {
            py::dict all;
            all["solution"] = matrix_array(a.solutions(), a.params().solution_size);
            all["objective"] = vector_array(std::vector<double>(a.objectives().begin(), a.objectives().end()));
            all["measures"] = matrix_array(a.measures(), a.params().measure_size);
            std::vector<std::int32_t> index(static_cast<std::size_t>(a.size()));
            for (std::size_t i = 0; i < index.size(); ++i) index[i] = static_cast<std::int32_t>(i);
            all["index"] = vector_array(index);
            if (!field) return all;
            if (!all.contains(*field))
              throw InputError("data(): unknown field '" + *field + "': use solution, objective, measures or index");
            return all[py::str(*field)];
          },
          py::arg("fields") = py::none(), "data() -> dict of arrays; data(field) -> that array (pyribs's names)")
      .def("__len__", &ProximityArchive::size)
      .def_property_readonly("empty", [](const ProximityArchive& a) { return a.size() == 0; })
      .def_property_readonly("stats", &ProximityArchive::stats)
      .def_property_readonly("solution_dim", [](const ProximityArchive& a) { return a.params().solution_size; })
      .def_property_readonly("measure_dim", [](const ProximityArchive& a) { return a.params().measure_size; })
      .def_property_readonly("k_neighbors", [](const ProximityArchive& a) { return a.params().k_neighbors; })
      .def_property_readonly("novelty_threshold", &ProximityArchive::novelty_threshold)
      .def_property_readonly("local_competition", [](const ProximityArchive& a) { return a.params().local_competition; })
      .def_property_readonly("qd_score_offset", [](const ProximityArchive& a) { return a.params().qd_offset; })
      .def(py::pickle([](const ProximityArchive& a) { return proximity_state(a); },
                      [](const py::tuple& s) { return proximity_from_state(s); }));
}

}  // namespace qdmeta::python
