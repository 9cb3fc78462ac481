// qdmeta.Algorithm: any registered algorithm built from a config dict, driven by ask/tell from
// Python or stepped with the library's threads. It pickles between steps as its resolved config,
// its Python task and meta-objective (by reference) and its checkpoint bytes (Algorithm::save),
// so an unpickled algorithm continues to the bits the original would have had.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "algorithm_archive.hpp"
#include "archive_handle.hpp"
#include "bindings.hpp"
#include "elite_arrays.hpp"
#include "numpy_arrays.hpp"
#include "pickled_state.hpp"
#include "python_build.hpp"
#include "python_evaluator.hpp"
#include "python_run.hpp"
#include "python_variation.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/run/checkpoint.hpp"
#include "toml_convert.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// A built run held for Python: the algorithm, its settings and its resolved config.
class PyAlgorithm {
 public:
  PyAlgorithm(const py::dict& config, std::optional<Task> task, std::shared_ptr<PythonMetaObjective> objective,
              const py::object& variation, const py::object& archive = py::none())
      : built_(build_from_python(config, PythonParts{task, objective})),
        task_(std::move(task)),
        objective_(std::move(objective)) {
    if (!archive.is_none()) start_from(archive);
    if (variation.is_none()) return;
    auto* map_elites = dynamic_cast<MapElites*>(&algorithm());
    if (map_elites == nullptr)
      throw py::value_error(fmt::format("Algorithm(variation=...) serves algorithm \"map-elites\" only, not \"{}\"",
                                        algorithm().name()));
    variation_ = variation;
    map_elites->set_variation(PythonVariation(variation));
  }

  Algorithm& algorithm() { return *built_.algorithm; }
  const Algorithm& algorithm() const { return *built_.algorithm; }

  // The genotypes of a one-job request (every request but QD-Meta's meta-objective batches).
  py::array_t<Real> ask() {
    std::span<const EvaluationJob> jobs;
    {
      const py::gil_scoped_release release;
      jobs = algorithm().ask();
    }
    jobs_ = jobs;
    if (jobs.size() != 1)
      throw py::value_error(fmt::format("{}: this request has {} jobs (batches of different tasks): use ask_jobs() and "
                                        "tell_jobs()",
                                        algorithm().name(), jobs.size()));
    return rows_copy(jobs[0].genotypes.data, jobs[0].genotypes.count, jobs[0].genotypes.genotype_size);
  }

  // Every job of the request: (task, genotypes) pairs.
  py::list ask_jobs() {
    {
      const py::gil_scoped_release release;
      jobs_ = algorithm().ask();
    }
    py::list out;
    for (const EvaluationJob& j : jobs_)
      out.append(py::make_tuple(*j.task, rows_copy(j.genotypes.data, j.genotypes.count, j.genotypes.genotype_size)));
    return out;
  }

  void tell(py::handle fitness, py::handle base_features, py::handle valid) {
    if (jobs_.size() > 1) throw py::value_error("tell(): the pending request has several jobs: use tell_jobs()");
    tell_blocks({py::make_tuple(fitness, base_features, valid)});
  }

  void tell_jobs(const py::sequence& results) {
    std::vector<py::tuple> blocks;
    for (const auto& r : results) {
      if (!py::isinstance<py::tuple>(r) && !py::isinstance<py::list>(r))
        throw py::type_error("tell_jobs(): each result must be (fitness, base_features[, valid])");
      const py::sequence s = r.cast<py::sequence>();
      blocks.push_back(py::make_tuple(s[0], s[1], s.size() > 2 ? py::object(s[2]) : py::object(py::none())));
    }
    tell_blocks(blocks);
  }

  // One step with the library's evaluator (Python tasks on this thread, once per batch).
  void step(int threads) {
    const py::gil_scoped_release release;
    if (!evaluator_ || threads_ != threads) {
      evaluator_ = std::make_unique<PythonAwareEvaluator>(threads);
      threads_ = threads;
    }
    algorithm().step(*evaluator_);
  }

  // To `budget` evaluations (default: the config's), in memory or into a fresh run directory.
  py::dict run(std::optional<std::int64_t> budget, std::optional<std::filesystem::path> out, int threads,
               bool overwrite, const py::object& progress) {
    if (algorithm().step_in_progress())
      throw Error(fmt::format("{}: run() in the middle of a step; finish it with tell() first", algorithm().name()));
    if (budget) {
      if (*budget < 1) throw py::value_error(fmt::format("run(): budget must be >= 1, got {}", *budget));
      built_.settings.budget = *budget;
      set_budget(built_.resolved, *budget);
      built_.settings.fingerprint = config_fingerprint(built_.resolved);
    }
    if (!out) return drive(built_, std::nullopt, threads, progress, nullptr);
    // A run directory describes a run from its config: only a fresh algorithm can start one.
    if (algorithm().generation() != 0)
      throw py::value_error(fmt::format("run(out_dir=...): the algorithm has done {} steps; a run directory needs a "
                                        "fresh one (or qdmeta.run(config, out_dir))",
                                        algorithm().generation()));
    return start_and_drive(built_, *out, threads, overwrite, progress);
  }

  const BuiltRun& built() const { return built_; }

  // Pickling: (format, resolved config, Python task or None, meta-objective or None, the
  // algorithm's checkpoint bytes, variation or None, the checksum of the format, config and
  // bytes: pickled_state.hpp). A built-in task is in the config already.
  py::tuple state() const {
    if (algorithm().step_in_progress())
      throw Error(fmt::format("{}: cannot pickle in the middle of a step (a request is pending or more are due); "
                              "finish the step with tell() first",
                              algorithm().name()));
    BinaryWriter out;
    algorithm().save(out);
    const py::object task = task_ && is_python_task(*task_) ? py::cast(*task_) : py::none();
    const py::object objective = objective_ ? py::cast(objective_) : py::none();
    const py::int_ format(kStateFormat);
    const py::dict config = dict_from_table(built_.resolved);
    const py::bytes bytes(out.bytes());
    const py::object centroids = centroids_of(algorithm());
    return py::make_tuple(format, config, task, objective, bytes, variation_,
                          state_checksum({format, config, bytes, centroids}), centroids);
  }

  static std::unique_ptr<PyAlgorithm> from_state(const py::tuple& s) {
    constexpr std::string_view who = "unpickling a qdmeta.Algorithm";
    if (s.size() < 1 || !py::isinstance<py::int_>(s[0]))
      throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
    if (!py::reinterpret_borrow<py::object>(s[0]).equal(py::int_(kStateFormat)))
      throw InputError(fmt::format("{}: state format {}, but this qdmeta reads format {}", who,
                                   py::str(s[0]).cast<std::string>(), kStateFormat));
    if (s.size() != 8 || !py::isinstance<py::dict>(s[1]) || !py::isinstance<py::bytes>(s[4]))
      throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
    auto a = std::make_unique<PyAlgorithm>(s[1].cast<py::dict>(), s[2].cast<std::optional<Task>>(),
                                           s[3].cast<std::shared_ptr<PythonMetaObjective>>(), py::object(s[5]));
    if (!s[7].is_none()) give_centroids(a->algorithm(), s[7], who);
    const std::string bytes = s[4].cast<std::string>();
    BinaryReader in(bytes, "the pickled qdmeta.Algorithm");
    {
      const py::gil_scoped_release release;
      a->algorithm().load(in);  // refuses a non-finite objective or measure
    }
    in.finish();
    // The values first, so a state built by hand with a bad value is named for it.
    check_run_elites(a->algorithm().elites(), who);
    check_state_checksum(s[6], state_checksum({s[0], s[1], s[4], s[7]}), who);
    return a;
  }

 private:
  // Algorithm(archive=...): MAP-Elites starts from a copy of a GridArchive of the grid its config
  // and task describe (the checkpoint then holds its elites, so pickles need nothing more).
  void start_from(const py::object& archive) {
    auto* map_elites = dynamic_cast<MapElites*>(&algorithm());
    if (map_elites == nullptr)
      throw py::value_error(fmt::format("Algorithm(archive=...) serves algorithm \"map-elites\" only, not \"{}\"",
                                        algorithm().name()));
    if (!py::isinstance<ArchiveHandle<GridArchive>>(archive))
      throw py::type_error(fmt::format("Algorithm(): archive must be a qdmeta.GridArchive, got {}",
                                       py::type::of(archive).attr("__name__").cast<std::string>()));
    const GridArchive& given = archive.cast<const ArchiveHandle<GridArchive>&>().archive;
    const GridArchiveParams &g = given.params(), &w = map_elites->archive().params();
    const auto shape = [](const GridArchiveParams& p) {
      return fmt::format("solution_dim {}, dims [{}], bounds [{}] to [{}], base_feature_dim {}, qd_offset {}",
                         p.solution_size, fmt::join(p.bins, ", "), fmt::join(bounds_of(p, false), ", "),
                         fmt::join(bounds_of(p, true), ", "), p.base_feature_size, p.qd_offset);
    };
    if (shape(g) != shape(w))
      throw InputError(fmt::format("Algorithm(archive=...): the archive has {}, but the config and task make {}",
                                   shape(g), shape(w)));
    map_elites->start_from(given);
  }

  static constexpr int kStateFormat = 3;  // 2: with its checksum; 3: with CVT-MAP-Elites's centroids

  // A CVT-MAP-Elites's centroids once made (None before, and for other algorithms): the pickle
  // carries them so that unpickling need not run k-means again.
  static py::object centroids_of(const Algorithm& algorithm) {
    const auto* cvt = dynamic_cast<const CvtMapElites*>(&algorithm);
    if (cvt == nullptr || !cvt->prepared()) return py::none();
    const RowMatrix& c = cvt->archive().centroids();
    return rows_copy(c.data(), c.rows(), c.cols());
  }

  static void give_centroids(Algorithm& algorithm, py::handle centroids, std::string_view who) {
    auto* cvt = dynamic_cast<CvtMapElites*>(&algorithm);
    const py::array raw = py::array::ensure(centroids);
    if (cvt == nullptr || !raw || raw.ndim() != 2)
      throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
    const FloatArray c = float_rows(raw, raw.shape(0), raw.shape(1), "centroids");
    cvt->give_centroids(std::make_shared<const RowMatrix>(Eigen::Map<const RowMatrix>(c.data(), c.shape(0), c.shape(1))));
  }

  void tell_blocks(const std::vector<py::tuple>& blocks) {
    if (jobs_.empty() || !algorithm().step_in_progress())
      throw Error(fmt::format("{}: tell() called with no pending ask()", algorithm().name()));
    if (blocks.size() != jobs_.size())
      throw py::value_error(fmt::format("{}: tell() got {} result blocks for a request of {} jobs", algorithm().name(),
                                        blocks.size(), jobs_.size()));
    std::vector<EvaluationBatch> results(blocks.size());
    for (std::size_t j = 0; j < blocks.size(); ++j) {
      const std::string who = jobs_.size() == 1 ? std::string("tell()") : fmt::format("tell_jobs(): job {}", j);
      results[j].resize(jobs_[j].out.count, jobs_[j].out.base_feature_size);
      copy_results(blocks[j][0], blocks[j][1], blocks[j][2], who, results[j].view());
    }
    const py::gil_scoped_release release;
    algorithm().tell(results);
    jobs_ = {};
  }

  BuiltRun built_;
  std::optional<Task> task_;  // as given, for pickling
  std::shared_ptr<PythonMetaObjective> objective_;
  py::object variation_ = py::none();  // as given, for pickling
  std::span<const EvaluationJob> jobs_;
  std::unique_ptr<Evaluator> evaluator_;
  int threads_ = -1;
};

}  // namespace

void bind_algorithms(py::module_& m) {
  py::class_<PyAlgorithm>(m, "Algorithm", R"doc(
Any registered algorithm ("map-elites", "cvt-map-elites", "aurora", "qd-meta", "cma-me", "cma-mae"), built from a
config dict with the keys of a TOML config (docs/config.md), e.g.
{"algorithm": "map-elites", "seed": 1, "archive": {"bins": [50, 50]}}. `task` (a qdmeta.Task)
replaces [task]; `meta_objective` (a qdmeta.MetaObjective) becomes QD-Meta's [meta_fitness].
`variation` (MAP-Elites only): f(parents, partners, seed) -> offspring, each row from two elites
drawn by the algorithm and f's own generator seeded with `seed`, genes in [0, 1].
`archive` (MAP-Elites only): a GridArchive of the grid the config and task make, whose elites
(copied) the first generation mutates.

ask() -> genotypes (n, genotype_size); evaluate them; tell(fitness, base_features, valid=None).
QD-Meta's requests may hold several jobs (its meta-objective's batches): ask_jobs() ->
[(task, genotypes)], tell_jobs([(fitness, base_features[, valid])]). step(threads=0) does one
step with the library's evaluator. The same config and seed give the same bits either way.)doc")
      .def(py::init<const py::dict&, std::optional<Task>, std::shared_ptr<PythonMetaObjective>, const py::object&,
                    const py::object&>(),
           py::arg("config"), py::arg("task") = py::none(), py::arg("meta_objective") = py::none(),
           py::arg("variation") = py::none(), py::arg("archive") = py::none())
      .def("ask", &PyAlgorithm::ask, "The next batch of genotypes to evaluate (a one-job request)")
      .def("ask_jobs", &PyAlgorithm::ask_jobs, "The next request as a list of (task, genotypes)")
      .def("tell", &PyAlgorithm::tell, py::arg("fitness"), py::arg("base_features"), py::arg("valid") = py::none(),
           "The evaluations of the last ask(): fitness (n,), base features (n, base_feature_size) in [0, 1], "
           "valid (n,) (default: all)")
      .def("tell_jobs", &PyAlgorithm::tell_jobs, py::arg("results"),
           "The evaluations of the last ask_jobs(), one (fitness, base_features[, valid]) per job")
      .def("step", &PyAlgorithm::step, py::arg("threads") = 0,
           "One step (a generation; for QD-Meta a meta-generation) with the library's threads (0: all cores)")
      .def("run", &PyAlgorithm::run, py::arg("budget") = py::none(), py::arg("out_dir") = py::none(),
           py::arg("threads") = 0, py::arg("overwrite") = false, py::arg("progress") = py::none(),
           "Steps to `budget` evaluations (default: the config's) with the library's threads; with out_dir, a fresh "
           "algorithm writes the run directory `qdmeta run` writes (checkpoints included). Returns summary.json's "
           "keys as a dict. Ctrl-C ends it at the next generation, then raises KeyboardInterrupt.")
      .def_property_readonly("name", [](const PyAlgorithm& a) { return a.algorithm().name(); })
      .def_property_readonly("generation", [](const PyAlgorithm& a) { return a.algorithm().generation(); })
      .def_property_readonly("evaluations",
                             [](const PyAlgorithm& a) {
                               const EvaluationCounters c = a.algorithm().counters();
                               py::dict d;
                               d["bottom"] = c.bottom;
                               d["meta"] = c.meta;
                               d["total"] = c.total();
                               return d;
                             })
      .def_property_readonly("step_in_progress", [](const PyAlgorithm& a) { return a.algorithm().step_in_progress(); })
      .def_property_readonly("stats", [](const PyAlgorithm& a) { return a.algorithm().stats(); })
      .def_property_readonly("config", [](const PyAlgorithm& a) { return dict_from_table(a.built().resolved); },
                             "Every key in force, defaults included")
      .def("as_pandas", [](const PyAlgorithm& a) { return elite_table_pandas(a.algorithm().elites()); },
           "The archive's elites as a pandas DataFrame with pyribs's columns")
      .def("data", [](const PyAlgorithm& a) { return elite_table_data(a.algorithm().elites()); },
           "The archive's elites (QD-Meta: the best map's) as numpy arrays")
      .def_property_readonly(
          "archive", [](PyAlgorithm& a) { return archive_copy(a.algorithm(), a.built().settings.seed); },
          "A copy of the archive the algorithm runs, taken now: a GridArchive (MAP-Elites; QD-Meta: the best map's "
          "of the latest meta-generation, over its target features), a CvtArchive with the centroids "
          "(CVT-MAP-Elites) or an UnstructuredArchive over the latent codes (AURORA); its sample_elites() is "
          "seeded with the config's seed. Adding to it leaves the algorithm as it was.")
      .def("retrieve", [](PyAlgorithm& a, py::handle measures) { return retrieve_from(a.algorithm(), measures); },
           py::arg("measures"),
           "retrieve(measures (n, measure_dim)) on the algorithm's archive (see `archive`), without copying it: "
           "(occupied (n,) bool, {index, objective, measures, solution})")
      .def(py::pickle([](const PyAlgorithm& a) { return a.state(); }, &PyAlgorithm::from_state));
}

}  // namespace qdmeta::python
