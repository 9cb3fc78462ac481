#include "qdmeta/algorithms/algorithm.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/algorithm_builder.hpp"

namespace qdmeta {

double offspring_bytes(double rows, const Task& task) {
  return rows * static_cast<double>(sizeof(Real)) * static_cast<double>(2 * task.genotype_size() + task.base_feature_size() + 2);
}

// The ask/tell protocol, shared by every algorithm.
void Algorithm::step(Evaluator& evaluator) {
  require_between_steps("step()");
  BinaryWriter undo;
  save_undo(undo);
  const EvaluationCounters before = counters_;
  try {
    before_step(evaluator);
    const bool confine = parallel_inside();
    do {
      std::span<const EvaluationJob> jobs;
      if (confine) evaluator.within_workers([&] { jobs = ask(); });
      else jobs = ask();
      // A single batch goes through evaluate(), which keeps per-thread task copies across calls.
      if (jobs.size() == 1) evaluator.evaluate(*jobs[0].task, jobs[0].genotypes, jobs[0].out);
      else evaluator.evaluate_jobs(jobs);
      if (confine) evaluator.within_workers([&] { tell(); });
      else tell();
    } while (in_step_);
  } catch (...) {
    counters_ = before;
    undo_step(undo.bytes());
    throw;  // the step's own error, whether or not the undo worked
  }
}

void Algorithm::undo_step(std::string_view undo) noexcept {
  jobs_.clear();
  pending_ = false;
  in_step_ = false;
  try {
    BinaryReader in(undo, "the state before the step");
    load_undo(in);
  } catch (...) {
    in_step_ = true;  // half undone: refuse to step on from here
  }
}

void Algorithm::save_undo(BinaryWriter& out) const {
  if (checkpointable()) save(out);
}

void Algorithm::load_undo(BinaryReader& in) {
  if (!checkpointable()) throw Error(fmt::format("{}: cannot undo a failed step", name()));
  load(in);
}

void Algorithm::load_generation_undo(BinaryReader& in) const {
  if (in.value<std::int64_t>("generation") != generation())
    throw Error(fmt::format("{}: the failed step had already changed the state", name()));
}

std::span<const EvaluationJob> Algorithm::ask() {
  if (pending_) throw Error(fmt::format("{}: ask() called again before tell() of the previous request", name()));
  jobs_.clear();
  next_request(jobs_);
  if (jobs_.empty()) throw Error(fmt::format("{}: made an empty request (a bug)", name()));
  pending_ = true;
  in_step_ = true;
  return jobs_;
}

void Algorithm::tell() {
  if (!pending_) throw Error(fmt::format("{}: tell() called with no pending ask()", name()));
  pending_ = false;
  const bool complete = take_results();
  // Counted only once taken: a tell() that throws counts nothing.
  for (const EvaluationJob& job : jobs_)
    if (job.bottom_level) counters_.bottom += job.genotypes.count;
  in_step_ = !complete;
}

namespace {
// Checks one caller-made result block against its job before anything is copied, so that a
// rejected tell() leaves the request pending.
void check_result_block(const std::string& algorithm, std::size_t j, const EvaluationJob& job,
                        const EvaluationBatch& r) {
  const Index rows = job.out.count;
  const auto valid_rows = static_cast<Index>(r.valid.size());
  if (r.fitness.size() != rows || r.base_features.rows() != rows || valid_rows != rows)
    throw InputError(fmt::format("{}: tell(): job {} (task '{}') has {} rows, but its result block has {} fitness "
                                 "values, {} base-feature rows and {} valid flags",
                                 algorithm, j, job.task->name(), rows, r.fitness.size(), r.base_features.rows(),
                                 valid_rows));
  if (r.base_features.cols() != job.out.base_feature_size)
    throw InputError(fmt::format("{}: tell(): job {} (task '{}') has {} base features, but its result block has {} "
                                 "base-feature columns",
                                 algorithm, j, job.task->name(), job.out.base_feature_size, r.base_features.cols()));
  for (Index i = 0; i < rows; ++i) {
    if (!r.valid[static_cast<std::size_t>(i)]) continue;
    if (!std::isfinite(r.fitness[i]))
      throw InputError(fmt::format("{}: tell(): job {} row {}: fitness {} is not finite", algorithm, j, i,
                                   r.fitness[i]));
    for (Index k = 0; k < r.base_features.cols(); ++k)
      if (!(r.base_features(i, k) >= 0 && r.base_features(i, k) <= 1))
        throw InputError(fmt::format("{}: tell(): job {} row {}: base feature {} is {}, outside [0, 1]{}", algorithm,
                                     j, i, k, r.base_features(i, k), kBaseFeatureRangeHint));
  }
}
}  // namespace

void Algorithm::tell(std::span<const EvaluationBatch> results) {
  if (!pending_) throw Error(fmt::format("{}: tell() called with no pending ask()", name()));
  if (results.size() != jobs_.size())
    throw InputError(fmt::format("{}: tell() got {} result blocks for a request of {} jobs", name(), results.size(),
                                 jobs_.size()));
  const std::string algorithm = name();
  for (std::size_t j = 0; j < jobs_.size(); ++j) check_result_block(algorithm, j, jobs_[j], results[j]);
  for (std::size_t j = 0; j < jobs_.size(); ++j) {
    const EvaluationView& out = jobs_[j].out;
    const EvaluationBatch& r = results[j];
    std::copy_n(r.fitness.data(), out.count, out.fitness);
    std::copy_n(r.base_features.data(), out.count * out.base_feature_size, out.base_features);
    std::copy_n(r.valid.data(), out.count, out.valid);
  }
  tell();
}

void Algorithm::require_between_steps(std::string_view what) const {
  if (in_step_)
    throw Error(fmt::format("{}: {} in the middle of a step (a request is pending or more are due); finish the step "
                            "with tell() first",
                            name(), what));
}

void Algorithm::save(BinaryWriter&) const {
  throw Error(fmt::format("algorithm '{}' cannot write checkpoints yet", name()));
}
void Algorithm::load(BinaryReader&) { throw Error(fmt::format("algorithm '{}' cannot read checkpoints yet", name())); }

void save_counters(BinaryWriter& out, const EvaluationCounters& c) {
  out.value(c.bottom);
  out.value(c.meta);
}

EvaluationCounters load_counters(BinaryReader& in) {
  EvaluationCounters c;
  c.bottom = in.value<std::int64_t>("bottom-level evaluations");
  c.meta = in.value<std::int64_t>("meta evaluations");
  if (c.bottom < 0 || c.meta < 0) in.fail("negative evaluation counters");
  return c;
}

std::unique_ptr<Algorithm> AlgorithmMaker::operator()() { return impl_->make(); }

}  // namespace qdmeta
