#include "qdmeta/algorithms/cma_mae.hpp"

#include <fmt/format.h>

#include <limits>
#include <utility>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "qdmeta/emitters/iso_line_emitter.hpp"

namespace qdmeta {

namespace {

// A variation emitter's params (Gaussian, iso+line): x0, batch_size and the gene bounds from p.
template <class Params>
Params variation_params(const CmaMaeParams& p, std::vector<double> x0) {
  Params v;
  v.x0 = std::move(x0);
  v.batch_size = p.emitter.batch_size;
  if (p.emitter.bounds != CmaBoundsHandling::kNone) {
    v.lower_bound = p.emitter.lower_bound;
    v.upper_bound = p.emitter.upper_bound;
  }
  return v;
}

GaussianEmitterParams gaussian_params(const CmaMaeParams& p, std::vector<double> x0) {
  auto g = variation_params<GaussianEmitterParams>(p, std::move(x0));
  g.sigma = p.sigma;
  return g;
}

IsoLineEmitterParams iso_line_params(const CmaMaeParams& p, std::vector<double> x0) {
  auto l = variation_params<IsoLineEmitterParams>(p, std::move(x0));
  l.iso_sigma = p.iso_sigma;
  l.line_sigma = p.line_sigma;
  return l;
}

}  // namespace

std::string to_string(EmitterKind value) { return std::string(enum_to_string(kEmitterKindNames, value)); }

void CmaMaeParams::validate() const {
  require(kCount, emitters);
  for (double gene : emitter.x0) require(kX0, gene);  // before the emitter's own x0 checks
  emitter.validate();
  switch (kind) {
    case EmitterKind::kEvolutionStrategy: break;
    case EmitterKind::kGaussian: gaussian_params(*this, emitter.x0).validate(); break;
    case EmitterKind::kIsoLine: iso_line_params(*this, emitter.x0).validate(); break;
    default: throw InputError(fmt::format("CmaMaeParams.kind = {} is invalid: must be one of evolution-strategy, "
                                          "gaussian, iso-line",
                                          static_cast<int>(kind)));
  }
  thresholds.validate();
  if (add_mode != AddMode::kSingle && add_mode != AddMode::kBatch)
    throw InputError(fmt::format("CmaMaeParams.add_mode = {} is invalid: must be single or batch", static_cast<int>(add_mode)));
}

std::unique_ptr<Emitter> make_configured_emitter(const CmaMaeParams& p, std::vector<double> x0, ElitePicker pick) {
  switch (p.kind) {
    case EmitterKind::kGaussian: return std::make_unique<GaussianEmitter>(gaussian_params(p, std::move(x0)), std::move(pick));
    case EmitterKind::kIsoLine: return std::make_unique<IsoLineEmitter>(iso_line_params(p, std::move(x0)), std::move(pick));
    case EmitterKind::kEvolutionStrategy: break;
  }
  EvolutionStrategyEmitterParams es = p.emitter;
  es.x0 = std::move(x0);
  return std::make_unique<EvolutionStrategyEmitter>(std::move(es), std::move(pick));
}

void add_cma_mae_memory(MemoryEstimate& m, const CmaMaeParams& p, double cells, const Task& task) {
  const auto genes = static_cast<double>(task.genotype_size());
  const auto emitters = static_cast<double>(p.emitters);
  m.add("the acceptance thresholds", "archive cells", cells * (sizeof(double) + 1));
  // CMA-ES keeps C, its eigenvectors, C^-1/2 and a work copy, n x n doubles each; the separable
  // one a few vectors of n (its mean, C's diagonal, two paths, a scale); the variation emitters
  // nothing beyond their batch.
  if (p.kind == EmitterKind::kEvolutionStrategy && p.emitter.es == EvolutionStrategyKind::kSepCmaEs)
    m.add("the emitters' separable CMA-ES", "emitters.count x genes", emitters * 5 * genes * sizeof(double));
  else if (p.kind == EmitterKind::kEvolutionStrategy)
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
  std::vector<std::unique_ptr<Emitter>> emitters;
  for (int i = 0; i < params_.emitters; ++i)
    emitters.push_back(make_configured_emitter(params_, params_.emitter.x0, elite_picker(*archive_)));
  scheduler_.emplace(*archive_, params_.thresholds, std::move(emitters), params_.add_mode);
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
  if (scheduler_ && params_.kind == EmitterKind::kEvolutionStrategy)  // the variation emitters never restart
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
