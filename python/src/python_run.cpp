#include "python_run.hpp"

#include <fmt/format.h>

#include "python_evaluator.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/io/run_lock.hpp"
#include "qdmeta/run/run.hpp"
#include "qdmeta/run/run_directory.hpp"
#include "qdmeta/run/summary.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace qdmeta::python {
namespace {

// After each generation, with the GIL: pending signals (Ctrl-C) stop the run, and the caller's
// progress callback hears how far it is. A Python exception from either is kept for the caller.
class PythonObserver final : public RunObserver {
 public:
  explicit PythonObserver(py::object progress) : progress_(std::move(progress)) {}

  RunVerdict after_step(const RunStatus& s) override {
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) return keep_error();
    if (!progress_.is_none()) {
      const ArchiveStats a = s.algorithm.stats();
      py::dict d;
      d["evals"] = s.evals;
      d["budget"] = s.settings.budget;
      d["generation"] = s.algorithm.generation();
      d["wall_seconds"] = s.clock.seconds();
      d["num_elites"] = a.num_elites;
      d["obj_max"] = a.obj_max;
      d["qd_score"] = a.qd_score;
      try {
        progress_(d);
      } catch (py::error_already_set& e) {
        error_ = std::move(e);
        return RunVerdict::kStop;
      }
    }
    return RunVerdict::kContinue;
  }

  // Raises what stopped the run, if anything did (with the GIL).
  void raise_if_stopped() {
    if (error_) {
      py::error_already_set e = std::move(*error_);
      error_.reset();
      throw e;
    }
  }

 private:
  RunVerdict keep_error() {
    error_.emplace();  // fetches the pending KeyboardInterrupt (or the handler's exception)
    return RunVerdict::kStop;
  }

  py::object progress_;
  std::optional<py::error_already_set> error_;
};

// summary.json as a dict, in the file's order (null: None).
py::dict summary_dict(const fs::path& dir) {
  const std::optional<RunSummary> summary = read_summary(dir);
  if (!summary) throw InputError(fmt::format("{} holds no summary.json", dir.string()));
  py::dict d;
  for (const auto& [key, value] : summary->values)
    d[py::str(key)] = std::visit(
        [](const auto& v) -> py::object {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) return py::none();
          else return py::cast(v);
        },
        value);
  return d;
}

// An in-memory run's result, with summary.json's keys where they apply.
py::dict result_dict(const BuiltRun& built, const RunResult& r) {
  py::dict d;
  d["algorithm"] = built.settings.algorithm;
  d["task"] = built.settings.task;
  d["stop_reason"] = std::string(enum_to_string(kStopReasonNames, r.reason));
  d["message"] = r.message;
  d["seed"] = built.settings.seed;
  d["budget"] = built.settings.budget;
  d["evals"] = r.evals;
  d["evals_bottom"] = r.counters.bottom;
  d["evals_meta"] = r.counters.meta;
  d["generations"] = r.generations;
  d["num_elites"] = r.stats.num_elites;
  d["coverage"] = r.stats.coverage;
  d["qd_score"] = r.stats.qd_score;
  d["norm_qd_score"] = r.stats.norm_qd_score;
  d["obj_max"] = r.stats.obj_max;
  d["obj_mean"] = r.stats.obj_mean;
  d["wall_seconds"] = r.wall_seconds;
  return d;
}

}  // namespace

py::dict drive(BuiltRun& built, const std::optional<fs::path>& out, int threads, const py::object& progress,
               const RunCursor* resume) {
  PythonObserver observer(progress);
  RunResult result;
  {
    const py::gil_scoped_release release;
    PythonAwareEvaluator evaluator(threads);
    if (out) {
      RunOptions options;
      options.resume = resume;
      options.observers = {&observer};
      result = run_to_budget(*built.algorithm, evaluator, built.settings, *out, options);
    } else {
      RunObserver* observers[] = {&observer};
      result = drive_run(*built.algorithm, evaluator, built.settings, observers);
    }
  }
  observer.raise_if_stopped();
  return out ? summary_dict(*out) : result_dict(built, result);
}

py::dict start_and_drive(BuiltRun& built, const fs::path& out, int threads, bool overwrite, const py::object& progress) {
  const RunLock lock(out, RunLock::Mode::kExclusive, RunLock::Missing::kCreate);
  // start_run_directory would refuse in the command line's words (--overwrite, qdmeta resume).
  const auto holds_run = [&] {
    for (const auto& f : run_files())
      if (path_taken(out / f)) return true;
    return false;
  };
  if (!overwrite && holds_run())
    throw InputError(fmt::format("{} already holds a run: pass overwrite=True to replace it, or continue it with "
                                 "qdmeta.resume('{}')",
                                 out.string(), out.string()));
  start_run_directory(out, built, "<python>", threads, overwrite);
  return drive(built, out, threads, progress, nullptr);
}

}  // namespace qdmeta::python
