#include "qdmeta/algorithms/map_elites.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void MapElitesParams::validate() const {
  require_range("map_elites.batch_size", batch_size, Index{1}, Index{10'000'000});
  require_range("map_elites.initial_population", initial_population, Index{1}, Index{100'000'000});
}

void random_genotypes(RowMatrix& genotypes, Rng& rng) {
  Real* g = genotypes.data();
  for (Index k = 0; k < genotypes.size(); ++k) g[k] = static_cast<Real>(rng.uniform());
}

namespace {
GridArchiveParams complete(GridArchiveParams p, const Task& task) {
  p.solution_size = task.genotype_size();
  p.qd_offset = task.qd_offset();
  return p;
}
}  // namespace

MapElites::MapElites(MapElitesParams params, Task task, std::unique_ptr<FeatureMap> feature_map,
                     GridArchiveParams archive, MutationParams mutation, std::uint64_t seed)
    : params_(params),
      task_(std::move(task)),
      feature_map_(std::move(feature_map)),
      archive_(complete(std::move(archive), task_)),
      mutation_(mutation),
      seed_(seed) {
  params_.validate();
  if (!feature_map_) throw InputError("map-elites: no feature-map given");
  if (feature_map_->input_size() != task_.base_feature_size())
    throw InputError(fmt::format("map-elites: the feature-map reads {} base features but task '{}' gives {}",
                                 feature_map_->input_size(), task_.name(), task_.base_feature_size()));
  if (feature_map_->output_size() != archive_.dimensions())
    throw InputError(fmt::format("map-elites: the feature-map gives {} target features but the archive has {} dimensions",
                                 feature_map_->output_size(), archive_.dimensions()));
}

void MapElites::next_request(std::vector<EvaluationJob>& jobs) {
  const Index n = task_.genotype_size();
  next_genotypes(archive_, params_, mutation_, seed_, generation_, n, genotypes_);
  evaluations_.resize(genotypes_.rows(), task_.base_feature_size());
  jobs.push_back({&task_, {genotypes_.data(), genotypes_.rows(), n}, evaluations_.view()});
}

bool MapElites::take_results() {
  insert_batch(archive_, *feature_map_, genotypes_, evaluations_, targets_);
  counters_.bottom += genotypes_.rows();
  ++generation_;
  return true;
}

EliteTable MapElites::elites() const { return archive_.elites(); }

// The ask/tell protocol, shared by every algorithm (declared in algorithm.hpp).
void Algorithm::step(Evaluator& evaluator) {
  require_between_steps("step()");
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
  in_step_ = !take_results();
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
        throw InputError(fmt::format("{}: tell(): job {} row {}: base feature {} is {}, outside [0, 1]", algorithm, j,
                                     i, k, r.base_features(i, k)));
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

void MapElites::save(BinaryWriter& out) const {
  require_between_steps("save()");
  out.tag("map_elites");
  out.value(generation_);
  save_counters(out, counters_);
  archive_.save(out);
}

void MapElites::load(BinaryReader& in) {
  require_between_steps("load()");
  in.expect_tag("map_elites");
  generation_ = in.value<std::int64_t>("generation");
  counters_ = load_counters(in);
  archive_.load(in);
}

}  // namespace qdmeta
