#include "qdmeta/algorithms/cma_mae.hpp"

#include <fmt/format.h>

#include <limits>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void CmaMaeParams::validate() const {
  require(kCount, emitters);
  emitter.validate();
  thresholds.validate();
}

void add_cma_mae_memory(MemoryEstimate& m, const CmaMaeParams& p, double cells, const Task& task) {
  const auto genes = static_cast<double>(task.genotype_size());
  const auto emitters = static_cast<double>(p.emitters);
  m.add("the acceptance thresholds", "archive cells", cells * (sizeof(double) + 1));
  // CMA-ES keeps C, its eigenvectors, C^-1/2 and a work copy, n x n doubles each.
  m.add("the emitters' CMA-ES", "emitters.count x genes^2", emitters * 4 * genes * genes * sizeof(double));
  m.add("a step's batch", "emitters.count x emitters.batch_size x genes", offspring_bytes(emitters * p.emitter.batch_size, task));
}

template <CellIndexedArchive A>
CmaMae<A>::CmaMae(CmaMaeParams params, Task task, std::unique_ptr<FeatureMap> feature_map, ArchiveSource<A> make_archive,
                  std::uint64_t seed)
    : params_(std::move(params)),
      task_(std::move(task)),
      feature_map_(std::move(feature_map)),
      make_archive_(std::move(make_archive)),
      seed_(seed) {
  params_.validate();
  if (static_cast<Index>(params_.emitter.x0.size()) != task_.genotype_size())
    throw InputError(fmt::format("{}: x0 has {} values, the task {} genes", params_.name, params_.emitter.x0.size(),
                                 task_.genotype_size()));
  if (!feature_map_ || feature_map_->input_size() != task_.base_feature_size())
    throw InputError(fmt::format("{}: the feature-map must take the task's {} base features", params_.name,
                                 task_.base_feature_size()));
  if (!make_archive_) throw InputError(fmt::format("{}: no archive source", params_.name));
}

template <CellIndexedArchive A>
void CmaMae<A>::make_parts(Evaluator* workers) {
  if (archive_) return;
  archive_.emplace(make_archive_(workers));
  if (archive_->solution_size() != task_.genotype_size() || archive_->dimensions() != feature_map_->output_size() ||
      !archive_->empty()) {
    const Index genes = archive_->solution_size(), dimensions = archive_->dimensions();
    archive_.reset();
    throw InputError(fmt::format("{}: the archive holds {} genes over {} measures; the task has {} genes and the "
                                 "feature-map makes {} measures (and it must start empty)",
                                 params_.name, genes, dimensions, task_.genotype_size(), feature_map_->output_size()));
  }
  make_scheduler();
}

template <CellIndexedArchive A>
void CmaMae<A>::make_scheduler() {
  scheduler_.reset();
  scheduler_.emplace(*archive_, params_.thresholds,
                     make_evolution_strategy_emitters(*archive_, params_.emitter, params_.emitters));
}

template <CellIndexedArchive A>
const A& CmaMae<A>::archive() const {
  if (!archive_) throw Error(fmt::format("{}: the archive is made by the first step (or prepare())", params_.name));
  return *archive_;
}

template <CellIndexedArchive A>
const Scheduler<A>& CmaMae<A>::scheduler() const {
  if (!scheduler_) throw Error(fmt::format("{}: the scheduler is made by the first step (or prepare())", params_.name));
  return *scheduler_;
}

template <CellIndexedArchive A>
ArchiveStats CmaMae<A>::stats() const {
  return archive_ ? archive_->stats() : ArchiveStats{};
}

template <CellIndexedArchive A>
EliteTable CmaMae<A>::elites() const {
  return archive_ ? archive_->elites() : EliteTable{};
}

template <CellIndexedArchive A>
std::vector<std::pair<std::string, double>> CmaMae<A>::summary_extras() const {
  std::int64_t restarts = 0;
  if (scheduler_)
    for (std::size_t i = 0; i < scheduler_->emitter_count(); ++i)
      restarts += static_cast<const EvolutionStrategyEmitter&>(scheduler_->emitter(i)).restarts();
  return {{"emitter_restarts", static_cast<double>(restarts)}};
}

template <CellIndexedArchive A>
void CmaMae<A>::next_request(std::vector<EvaluationJob>& jobs) {
  if (!archive_) make_parts(nullptr);
  Rng rng = Rng::stream(seed_, {key(StreamKey::kVariation), static_cast<std::uint64_t>(generation_)});
  const RowMatrix& batch = scheduler_->ask(rng);
  evaluations_.resize(batch.rows(), task_.base_feature_size());
  jobs.push_back({&task_, {batch.data(), batch.rows(), batch.cols()}, evaluations_.view()});
}

template <CellIndexedArchive A>
bool CmaMae<A>::take_results() {
  const Index rows = evaluations_.size();
  // A task may leave an invalid row's results undefined (even NaN): such a row enters no cell,
  // and its neutral values keep the emitters' rankings finite.
  for (Index r = 0; r < rows; ++r) {
    if (evaluations_.valid[static_cast<std::size_t>(r)]) continue;
    evaluations_.base_features.row(r).setZero();
    evaluations_.fitness[r] = std::numeric_limits<Real>::lowest();
  }
  measures_.resize(rows, feature_map_->output_size());
  feature_map_->map(evaluations_.base_features.data(), rows, measures_.data());
  scheduler_->tell({evaluations_.fitness.data(), static_cast<std::size_t>(rows)}, measures_, evaluations_.valid);
  ++generation_;
  return true;
}

template <CellIndexedArchive A>
void CmaMae<A>::save(BinaryWriter& out) const {
  require_between_steps("save()");
  out.tag("cma_mae");
  out.value(generation_);
  save_counters(out, counters());
  out.boolean(archive_.has_value());
  if (!archive_) return;
  archive_->save(out);
  scheduler_->save(out);
}

template <CellIndexedArchive A>
void CmaMae<A>::load(BinaryReader& in) {
  require_between_steps("load()");
  in.expect_tag("cma_mae");
  generation_ = in.value<std::int64_t>("generation");
  restore_counters(load_counters(in));
  if (!in.boolean("archive flag")) return;
  make_parts(nullptr);
  archive_->load(in);
  scheduler_->load(in);
}

template <CellIndexedArchive A>
void CmaMae<A>::save_undo(BinaryWriter& out) const {
  save_generation_undo(out);
  out.boolean(scheduler_.has_value());
  if (scheduler_) scheduler_->save(out);
}

template <CellIndexedArchive A>
void CmaMae<A>::load_undo(BinaryReader& in) {
  load_generation_undo(in);
  if (in.boolean("scheduler flag")) scheduler_->load(in);
  else if (scheduler_) make_scheduler();  // the failed first step made it and asked it: made afresh
}

template class CmaMae<GridArchive>;
template class CmaMae<CvtArchive>;

}  // namespace qdmeta
