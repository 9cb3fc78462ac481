// qdmeta.Scheduler and qdmeta.BanditScheduler (emitters/scheduler.hpp, bandit_scheduler.hpp)
// over a GridArchive or CvtArchive whose learning_rate and threshold_min give the thresholds,
// with pyribs's names. Both pickle with their archives and emitters, and an unpickled one
// continues to the same bits.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "archive_handle.hpp"
#include "bindings.hpp"
#include "emitter_handle.hpp"
#include "numpy_arrays.hpp"
#include "pickled_state.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/emitters/bandit_scheduler.hpp"
#include "qdmeta/emitters/scheduler.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// Of the scheduler state tuples: 2 adds the add mode at the end; 1 (before it) loads as "single".
constexpr int kSchedulerStateFormat = 2;

// qdmeta.Scheduler and qdmeta.BanditScheduler: the C++ scheduler over the archive's type, with
// the Python objects it uses.
struct SchedulerHandle {
  py::object archive, result_archive;
  py::list emitters;
  std::optional<BanditParams> bandit;  // a BanditScheduler's
  AddMode add_mode = AddMode::kSingle;
  std::variant<std::unique_ptr<Scheduler<GridArchive>>, std::unique_ptr<Scheduler<CvtArchive>>,
               std::unique_ptr<BanditScheduler<GridArchive>>, std::unique_ptr<BanditScheduler<CvtArchive>>>
      scheduler;

  const char* name() const { return bandit ? "BanditScheduler" : "Scheduler"; }
  const char* emitters_name() const { return bandit ? "emitter_pool" : "emitters"; }

  Index rows() const { return std::visit([](const auto& s) { return s->batch_size(); }, scheduler); }
  Index measure_dim() const {
    return std::visit([](const auto& s) { return s->archive().dimensions(); }, scheduler);
  }
};

// A handle of its own type for each Python class (pybind11 binds a type once).
struct BanditSchedulerHandle final : SchedulerHandle {};

template <class A>
void make_scheduler_over(SchedulerHandle& h, ArchiveHandle<A>& archive) {
  std::vector<std::unique_ptr<Emitter>> wrapped;
  for (const auto e : h.emitters) wrapped.push_back(std::make_unique<HandleEmitter>(e.cast<std::shared_ptr<EmitterHandle>>()));
  if (h.bandit)
    h.scheduler = std::make_unique<BanditScheduler<A>>(archive.archive, archive.thresholds, std::move(wrapped), *h.bandit,
                                                       h.add_mode);
  else
    h.scheduler = std::make_unique<Scheduler<A>>(archive.archive, archive.thresholds, std::move(wrapped), h.add_mode);
}

// pyribs's add_mode names: "single" (the default here) and "batch" (pyribs's default).
AddMode add_mode_from_string(const std::string& add_mode) {
  if (add_mode == "single") return AddMode::kSingle;
  if (add_mode == "batch") return AddMode::kBatch;
  throw InputError(fmt::format("add_mode = '{}' is not 'single' or 'batch'", add_mode));
}

void add_to_result_archive(py::handle result, const EliteBatch& batch) {
  if (py::isinstance<ArchiveHandle<GridArchive>>(result))
    result.cast<ArchiveHandle<GridArchive>&>().archive.add_batch(batch);
  else
    result.cast<ArchiveHandle<CvtArchive>&>().archive.add_batch(batch);
}

Index measure_dim_of(py::handle archive) {
  if (py::isinstance<ArchiveHandle<GridArchive>>(archive)) return archive.cast<ArchiveHandle<GridArchive>&>().archive.dimensions();
  return archive.cast<ArchiveHandle<CvtArchive>&>().archive.dimensions();
}

// `bandit`: a BanditScheduler of those params; none: a Scheduler.
template <class H>
H make_scheduler(py::object archive, py::handle emitters, py::object result_archive, std::optional<BanditParams> bandit,
                 AddMode add_mode) {
  H h;
  h.bandit = bandit;
  h.add_mode = add_mode;
  const char* e = h.emitters_name();
  const Index genes = archive_solution_dim(archive);  // TypeError unless a Grid or CVT archive
  h.emitters = py::list(py::reinterpret_borrow<py::object>(emitters));
  if (h.emitters.empty()) throw InputError(fmt::format("{} is empty: give the {} at least one emitter", e, h.name()));
  if (bandit) bandit->validate(h.emitters.size());
  for (std::size_t i = 0; i < h.emitters.size(); ++i) {
    if (!py::isinstance<EmitterHandle>(h.emitters[i]))
      throw py::type_error(fmt::format("{}[{}] is not a qdmeta emitter", e, i));
    if (!h.emitters[i].template cast<EmitterHandle&>().archive.is(archive))
      throw InputError(fmt::format("{}[{}] was made over another archive: give each emitter the scheduler's archive", e, i));
    for (std::size_t j = 0; j < i; ++j)
      if (h.emitters[j].is(h.emitters[i]))
        throw InputError(fmt::format("{0}[{1}] is {0}[{2}]: give each emitter once", e, i, j));
  }
  if (!result_archive.is_none()) {
    if (result_archive.is(archive)) throw InputError("result_archive is the archive: give another archive or None");
    if (archive_solution_dim(result_archive) != genes || measure_dim_of(result_archive) != measure_dim_of(archive))
      throw InputError("result_archive has another solution_dim or measure_dim than the archive");
  }
  if (py::isinstance<ArchiveHandle<GridArchive>>(archive))
    make_scheduler_over(h, archive.cast<ArchiveHandle<GridArchive>&>());
  else
    make_scheduler_over(h, archive.cast<ArchiveHandle<CvtArchive>&>());
  h.archive = std::move(archive);
  h.result_archive = std::move(result_archive);
  return h;
}

void tell(SchedulerHandle& h, py::handle objective, py::handle measures) {
  const Index rows = h.rows();
  const FloatArray o = float_rows(objective, rows, -1, "objective");
  const FloatArray m = float_rows(measures, rows, h.measure_dim(), "measures");
  for (Index r = 0; r < rows; ++r) {
    if (!std::isfinite(o.data()[r]))
      throw InputError(fmt::format("{}.tell: objective[{}] = {} is invalid: must be finite", h.name(), r, o.data()[r]));
    for (Index d = 0; d < h.measure_dim(); ++d)
      if (!std::isfinite(m.data()[r * h.measure_dim() + d]))
        throw InputError(fmt::format("{}.tell: measures[{}, {}] = {} is invalid: must be finite", h.name(), r, d,
                                     m.data()[r * h.measure_dim() + d]));
  }
  const std::span<const Real> objectives(o.data(), static_cast<std::size_t>(rows));
  const RowsView measure_rows(m.data(), rows, h.measure_dim());
  std::visit(
      [&](auto& s) {
        s->tell(objectives, measure_rows);
        if (!h.result_archive.is_none())
          add_to_result_archive(h.result_archive, EliteBatch{s->solutions(), objectives, measure_rows, {}, {}});
      },
      h.scheduler);
}

py::tuple scheduler_state(const SchedulerHandle& h) {
  BinaryWriter out;
  std::visit([&](const auto& s) { s->save(out); }, h.scheduler);
  const py::int_ format(kSchedulerStateFormat);
  const py::bytes bytes(out.bytes());
  const py::str add_mode(to_string(h.add_mode));
  if (!h.bandit) {
    const py::int_ checksum(state_checksum({format, bytes, add_mode}));
    return py::make_tuple(format, h.archive, h.emitters, h.result_archive, bytes, checksum, add_mode);
  }
  const py::tuple params = py::make_tuple(h.bandit->num_active, h.bandit->reselect == BanditReselect::kAll ? "all" : "terminated",
                                          h.bandit->zeta);
  const py::int_ checksum(state_checksum({format, bytes, params, add_mode}));
  return py::make_tuple(format, h.archive, h.emitters, h.result_archive, bytes, checksum, params, add_mode);
}

template <class H>
H scheduler_from_state(const py::tuple& s) {
  constexpr bool is_bandit = std::is_same_v<H, BanditSchedulerHandle>;
  const char* who = is_bandit ? "unpickling a qdmeta.BanditScheduler" : "unpickling a qdmeta.Scheduler";
  const std::size_t fields = is_bandit ? 7 : 6;  // format 1's; format 2 adds the add mode
  const auto format = py::reinterpret_borrow<py::object>(s[0]);
  const bool has_mode = format.equal(py::int_(kSchedulerStateFormat));
  if (!(has_mode || format.equal(py::int_(1))) || s.size() != fields + (has_mode ? 1 : 0) || !py::isinstance<py::list>(s[2]) ||
      !py::isinstance<py::bytes>(s[4]) || (is_bandit && !py::isinstance<py::tuple>(s[6])) ||
      (has_mode && !py::isinstance<py::str>(s[fields])))
    throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
  std::uint64_t checksum = 0;
  if (is_bandit) checksum = has_mode ? state_checksum({s[0], s[4], s[6], s[fields]}) : state_checksum({s[0], s[4], s[6]});
  else checksum = has_mode ? state_checksum({s[0], s[4], s[fields]}) : state_checksum({s[0], s[4]});
  check_state_checksum(s[5], checksum, who);
  std::optional<BanditParams> bandit;
  if constexpr (is_bandit) {
    const auto p = s[6].cast<py::tuple>();
    bandit = BanditParams{p[0].cast<int>(), bandit_reselect_from_string(p[1].cast<std::string>()), p[2].cast<double>()};
  }
  const AddMode add_mode = has_mode ? add_mode_from_string(s[fields].cast<std::string>()) : AddMode::kSingle;
  H h = make_scheduler<H>(py::reinterpret_borrow<py::object>(s[1]), s[2], py::reinterpret_borrow<py::object>(s[3]), bandit,
                          add_mode);
  const std::string bytes = s[4].cast<std::string>();
  BinaryReader in(bytes, is_bandit ? "the pickled BanditScheduler" : "the pickled Scheduler");
  std::visit([&](auto& scheduler) { scheduler->load(in); }, h.scheduler);
  in.finish();
  return h;
}

// What both classes have: ask, tell, the archives, emitters and thresholds, pickling.
template <class H>
void bind_scheduler_methods(py::class_<H>& cls) {
  cls.def("ask",
           [](H& h) {
             Rng unused;  // each emitter asks with its own stream
             return std::visit(
                 [&](auto& s) {
                   const RowMatrix& x = s->ask(unused);
                   return rows_copy(x.data(), x.rows(), x.cols());
                 },
                 h.scheduler);
           },
           "The next batch: an (n, solution_dim) float32 array, every emitter's rows in emitter order")
      .def("tell", [](H& h, py::handle objective, py::handle measures) { tell(h, objective, measures); }, py::arg("objective"), py::arg("measures"),
           "The objective (n,) and measures (n, measure_dim) of the last ask()'s rows, in its order")
      .def_property_readonly("archive", [](const H& h) { return h.archive; })
      .def_property_readonly("result_archive", [](const H& h) { return h.result_archive; })
      .def_property_readonly("emitters", [](const H& h) { return py::list(h.emitters); })
      .def_property_readonly("thresholds",
                             [](const H& h) {
                               return std::visit(
                                   [](const auto& s) {
                                     const CellThresholds& t = s->thresholds();
                                     auto out = new_array<double>({t.cells()});  // numpy 2: not array_t(n)
                                     for (Index c = 0; c < t.cells(); ++c) out.mutable_data()[c] = t.threshold(c);
                                     return out;
                                   },
                                   h.scheduler);
                             },
                             "Each cell's CMA-MAE threshold (threshold_min where never reached), by cell index")
      .def_property_readonly(
          "add_info",
          [](const H& h) {
            return std::visit(
                [](const auto& s) {
                  const auto outcomes = s->outcomes();
                  const auto rows = static_cast<py::ssize_t>(outcomes.size());
                  auto status = new_array<std::int32_t>({rows});
                  auto value = new_array<double>({rows});
                  for (py::ssize_t r = 0; r < rows; ++r) {
                    status.mutable_data()[r] = static_cast<std::int32_t>(outcomes[static_cast<std::size_t>(r)].status);
                    value.mutable_data()[r] = outcomes[static_cast<std::size_t>(r)].improvement;
                  }
                  py::dict info;
                  info["status"] = status;
                  info["value"] = value;
                  return info;
                },
                h.scheduler);
          },
          "The last tell's rows as the thresholds took them, as pyribs's archive.add returns them: status "
          "(int32: 0 not added, 1 improved, 2 new) and value (objective minus the cell's threshold)")
      .def(py::pickle([](const H& h) { return scheduler_state(h); },
                      [](const py::tuple& s) { return scheduler_from_state<H>(s); }));

}

}  // namespace

void bind_schedulers(py::module_& m) {
  py::class_<SchedulerHandle> plain(m, "Scheduler", R"doc(
CMA-ME / CMA-MAE's ask/tell loop, as pyribs's Scheduler: ask() stacks every emitter's batch (an
(n, solution_dim) float32 array, emitters in order); tell(objective, measures) adds every row to
the archive under its thresholds (learning_rate, threshold_min), tells each emitter its rows'
outcomes, and adds them to result_archive when given. The archive keeps each cell's best elite
whatever learning_rate is; the per-cell thresholds are the scheduler's (`thresholds`). The rows
are offered to the thresholds one at a time, in order, with add_mode "single" (the default, CMA-MAE's
Algorithm 1); with "batch" (pyribs's default) every row is scored against the thresholds before
the batch, and each cell's threshold moves once, by the paper's batch rule.)doc");
  plain.def(py::init([](py::object archive, py::handle emitters, py::object result_archive, const std::string& add_mode) {
                return make_scheduler<SchedulerHandle>(std::move(archive), emitters, std::move(result_archive), {},
                                                       add_mode_from_string(add_mode));
              }),
              py::arg("archive"), py::arg("emitters"), py::arg("result_archive") = py::none(), py::kw_only(),
              py::arg("add_mode") = "single");
  bind_scheduler_methods(plain);

  py::class_<BanditSchedulerHandle> bandit(m, "BanditScheduler", R"doc(
pyribs's BanditScheduler: a Scheduler over a pool of emitters that asks num_active of them at a
time. Those chosen again (reselect "terminated": whose run ended, and every emitter without
runs; "all": every active one) are replaced by the emitters of highest UCB1 value, successes /
rows + zeta sqrt(ln(all successes) / rows), a success being a row the archive's thresholds took.
ask() stacks the active emitters' batches in pool order; `active` flags them. add_mode as
Scheduler's.)doc");
  bandit
      .def(py::init([](py::object archive, py::handle emitter_pool, py::object result_archive, int num_active,
                       const std::string& reselect, double zeta, const std::string& add_mode) {
             return make_scheduler<BanditSchedulerHandle>(
                 std::move(archive), emitter_pool, std::move(result_archive),
                 BanditParams{num_active, bandit_reselect_from_string(reselect), zeta}, add_mode_from_string(add_mode));
           }),
           py::arg("archive"), py::arg("emitter_pool"), py::arg("result_archive") = py::none(), py::kw_only(),
           py::arg("num_active"), py::arg("reselect") = "terminated", py::arg("zeta") = 0.05,
           py::arg("add_mode") = "single")
      .def_property_readonly("emitter_pool", [](const BanditSchedulerHandle& h) { return py::list(h.emitters); })
      .def_property_readonly("active",
                             [](const BanditSchedulerHandle& h) {
                               return std::visit(
                                   [](const auto& s) {
                                     std::vector<bool> flags;
                                     if constexpr (requires { s->bandit(); })
                                       for (const std::uint8_t f : s->bandit().active()) flags.push_back(f != 0);
                                     return py::array(py::cast(flags));
                                   },
                                   h.scheduler);
                             },
                             "One flag per pool emitter: those the last ask() asked (none before it)");
  bind_scheduler_methods(bandit);
}

}  // namespace qdmeta::python
