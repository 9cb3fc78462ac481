#include "qdmeta/algorithms/qd_meta.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>

#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta_emitters.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/parallel.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/meta/rebuild.hpp"

namespace qdmeta {

void QdMetaParams::validate() const {
  require(kMetaPopulation, meta_population);
  require(kBatchSize, batch_size);
  require(kInitialPopulation, initial_population);
  require(kDatabaseCapacity, database_capacity);
  require(kHidden, hidden);
  require(kSigmoidScale, sigmoid_scale);
  require(kCmaSigma, cma_sigma);
  if (bottom_level != BottomLevel::kCmaMae) return;
  emitters.validate();
  if (const Index rows = Index{emitters.emitters} * emitters.emitter.batch_size; batch_size != rows)
    throw InputError(fmt::format("qd_meta.batch_size = {} must be emitters.count x emitters.batch_size = {} with "
                                 "qd_meta.bottom_level = \"cma-mae\" (a generation is one batch of every emitter)",
                                 batch_size, rows));
}

namespace {

GridArchiveParams complete_archive(GridArchiveParams p, const Task& task) {
  p.solution_size = task.genotype_size();
  p.base_feature_size = task.base_feature_size();
  p.qd_offset = task.qd_offset();
  return p;
}

NeuralFeatureMapShape make_shape(const QdMetaParams& p, const Task& task, const GridArchiveParams& archive) {
  NeuralFeatureMapShape s;
  s.inputs = task.base_feature_size();
  s.hidden = p.hidden;
  s.outputs = static_cast<Index>(archive.bins.size());
  s.alpha = p.sigmoid_scale;
  return s;
}

CmaEsParams make_cma(const QdMetaParams& p, Index dimension) {
  CmaEsParams c;
  c.dimension = static_cast<int>(dimension);
  c.population_size = static_cast<int>(p.meta_population);
  c.initial_sigma = p.cma_sigma;
  c.initial_mean = 0.0;
  c.lower_bound = -1.0;
  c.upper_bound = 1.0;
  c.bounds = p.cma_bounds;
  c.frozen = p.frozen;
  c.small_population = p.cma_small_population;
  return c;
}

}  // namespace

void add_qd_meta_memory(MemoryEstimate& m, const QdMetaParams& p, const GridArchiveParams& grid, const Task& task,
                        int max_generations) {
  constexpr auto kFloat = static_cast<double>(sizeof(Real));
  const auto lambda = static_cast<double>(p.meta_population);
  const auto n = static_cast<double>(task.genotype_size());
  const auto nb = static_cast<double>(task.base_feature_size());
  const auto dims = static_cast<double>(grid.bins.size());
  const double k = static_cast<double>(p.hidden) * (nb + 1 + dims) + 1;  // the feature-map's weights
  GridArchiveParams map_archive = grid;  // as the constructor makes each map's archive
  map_archive.solution_size = task.genotype_size();
  map_archive.base_feature_size = task.base_feature_size();
  m.add("the meta-population's archives", "(qd_meta.meta_population + 1) x archive.bins (cells) x genes",
        (lambda + 1) * grid_archive_bytes(map_archive) + lambda * grid_cells(grid) * (16 + kFloat * dims));
  m.add("the circular database", "qd_meta.database_capacity x (genes + 2 x base features)",
        static_cast<double>(p.database_capacity) * kFloat * (n + 2 * nb + 1));
  m.add("every map's offspring of one meta-generation",
        "qd_meta.meta_population x qd_meta.batch_size x control.max_generations (or generations) x genes",
        lambda * offspring_bytes(static_cast<double>(max_generations) * static_cast<double>(p.batch_size), task));
  m.add("the archives as the meta-objective reads them", "qd_meta.meta_population x archive.bins (cells) x "
        "(genes + target features + base features + 1)",
        lambda * grid_cells(grid) * kFloat * (n + dims + nb + 1));
  m.add("CMA-ES's matrices", "(qd_meta.hidden x (base features + target features + 1))^2",
        4 * k * k * sizeof(double) + lambda * k * sizeof(double));
  m.add("the initial population", "qd_meta.initial_population x genes",
        offspring_bytes(static_cast<double>(p.initial_population), task));
  if (p.bottom_level == BottomLevel::kCmaMae) {
    const double cells = lambda * grid_cells(grid);
    m.add("the maps' acceptance thresholds", "qd_meta.meta_population x archive.bins (cells)",
          cells * (sizeof(double) + 1));
    const double emitters = lambda * static_cast<double>(p.emitters.emitters);
    const bool es = p.emitters.kind == EmitterKind::kEvolutionStrategy;
    if (es && p.emitters.emitter.es == EvolutionStrategyKind::kSepCmaEs)
      m.add("the maps' emitters' separable CMA-ES", "qd_meta.meta_population x emitters.count x genes",
            emitters * 5 * n * sizeof(double));
    else if (es)
      m.add("the maps' emitters' CMA-ES", "qd_meta.meta_population x emitters.count x genes^2",
            emitters * 4 * n * n * sizeof(double));
  }
}

QdMeta::QdMeta(QdMetaParams params, Task task, std::unique_ptr<MetaObjective> meta_objective,
               GridArchiveParams archive, MutationParams mutation, std::unique_ptr<GenerationController> controller,
               std::uint64_t seed)
    : params_((params.validate(), params)),
      task_(std::move(task)),
      meta_objective_(std::move(meta_objective)),
      mutation_(mutation),
      controller_(std::move(controller)),
      seed_(seed),
      shape_(make_shape(params_, task_, archive)),
      cma_(make_cma(params_, shape_.weight_count())),
      database_(params_.database_capacity, task_.genotype_size(), task_.base_feature_size()),
      best_archive_(complete_archive(archive, task_)) {
  if (!meta_objective_) throw InputError("qd-meta: no meta-objective given");
  if (!controller_) throw InputError("qd-meta: no generation controller given");
  if (task_.base_feature_size() < 1)
    throw InputError(fmt::format("qd-meta: task '{}' has no base features to build feature-maps from", task_.name()));
  const auto lambda = static_cast<std::size_t>(params_.meta_population);
  if (params_.bottom_level == BottomLevel::kCmaMae) {
    if (static_cast<Index>(params_.emitters.emitter.x0.size()) != task_.genotype_size())
      throw InputError(fmt::format("qd-meta: emitters' x0 has {} values, the task {} genes",
                                   params_.emitters.emitter.x0.size(), task_.genotype_size()));
    schedulers_.resize(lambda);
  }
  archives_.assign(lambda, best_archive_);
  maps_.resize(lambda);
  offspring_.resize(lambda);
  evaluations_.resize(lambda);
  blocks_.resize(lambda);
  block_evaluations_.resize(lambda);
  targets_.resize(lambda);
  meta_tasks_ = meta_objective_->tasks();
  elites_.resize(lambda);
  plans_.resize(lambda);
  planned_.assign(lambda, std::uint8_t{0});
  meta_evaluations_.resize(lambda);
  meta_results_.resize(lambda);
  meta_fitness_.resize(lambda);
}

namespace {

// body(0) ... body(n - 1), on oneTBB when `parallel`: every index owns its map's buffers and
// streams, so the result does not depend on the split (step() confines it to the evaluator's
// workers).
void for_each_map(Index n, bool parallel, const std::function<void(Index)>& body) {
  if (!parallel || n < 2) {
    for (Index i = 0; i < n; ++i) body(i);
    return;
  }
  parallel_indices(n, body);
}

}  // namespace

void QdMeta::next_request(std::vector<EvaluationJob>& jobs) {
  const Index n = task_.genotype_size();
  if (phase_ == Phase::kIdle) {
    if (meta_generation_ == 0 && database_.total_inserted() == 0 && counters().bottom == 0) {
      seed_genotypes_.resize(params_.initial_population, n);
      Rng rng = Rng::stream(seed_, {key(StreamKey::kInitialPopulation)});
      random_genotypes(seed_genotypes_, rng);
      seed_evaluations_.resize(seed_genotypes_.rows(), task_.base_feature_size());
      jobs.push_back({&task_, {seed_genotypes_.data(), seed_genotypes_.rows(), n}, seed_evaluations_.view()});
      phase_ = Phase::kSeeding;
      return;
    }
    begin_meta_generation();
  } else if (phase_ == Phase::kSeeding) {
    begin_meta_generation();
  }
  const auto lambda = params_.meta_population;
  if (phase_ == Phase::kGenerations) {
    // Generation 0's offspring are made here; later ones by the tell() before (see take_results).
    if (next_generation_ == 0) for_each_map(lambda, true, [&](Index i) { vary_map(i, 0); });
    for (Index i = 0; i < lambda; ++i) {
      const auto m = static_cast<std::size_t>(i);
      jobs.push_back({&task_, {blocks_[m].data(), params_.batch_size, n}, block_evaluations_[m].view()});
    }
    return;
  }
  // kMetaScoring: every map's batches, map-major.
  for (Index i = 0; i < lambda; ++i) {
    const auto m = static_cast<std::size_t>(i);
    if (!planned_[m]) continue;
    for (std::size_t k = 0; k < plans_[m].batches.size(); ++k) {
      const MetaBatch& b = plans_[m].batches[k];
      jobs.push_back({&meta_tasks_[static_cast<std::size_t>(b.task)],
                      {b.genotypes.data(), b.genotypes.rows(), b.genotypes.cols()}, meta_evaluations_[m][k].view(),
                      /*bottom_level=*/false});
    }
  }
}

bool QdMeta::take_results() {
  if (phase_ == Phase::kSeeding) {
    store(seed_genotypes_, seed_evaluations_);
    return false;  // the meta-generation follows in the same step
  }
  const auto lambda = params_.meta_population;
  if (phase_ == Phase::kGenerations) {
    const Index batch = params_.batch_size;
    const int g = next_generation_;
    const bool last = g + 1 == generations_;
    // One parallel pass per generation: each map inserts its batch, then makes its next batch
    // (or, on the last generation, plans its meta-fitness when that may run in parallel). The
    // same work in separate passes gives the same bits; fusing them saves a fork-join.
    const bool plan_here = last && task_.shareable();
    for_each_map(lambda, true, [&](Index i) {
      const auto m = static_cast<std::size_t>(i);
      const RowMatrix& block = blocks_[m];
      EvaluationBatch& e = block_evaluations_[m];
      if (schedulers_.empty()) insert_batch(archives_[m], *maps_[m], block, e, targets_[m]);
      else tell_map_emitters(*schedulers_[m], *maps_[m], e, targets_[m]);
      offspring_[m].middleRows(g * batch, batch) = block;
      evaluations_[m].fitness.segment(g * batch, batch) = e.fitness;
      evaluations_[m].base_features.middleRows(g * batch, batch) = e.base_features;
      std::copy(e.valid.begin(), e.valid.end(), evaluations_[m].valid.begin() + static_cast<std::ptrdiff_t>(g * batch));
      if (!last) vary_map(i, g + 1);
      else if (plan_here) plan_map(i);
    });
    if (!last) {
      ++next_generation_;
      return false;
    }
    if (!plan_here)
      for (Index i = 0; i < lambda; ++i) plan_map(i);
    if (meta_objective_simulates()) {
      phase_ = Phase::kMetaScoring;
      return false;
    }
    score_meta_fitness();
  } else {
    score_meta_fitness();
  }
  finish_meta_generation();
  return true;
}

// Samples the meta-population, rebuilds every map from the whole database, and chooses G.
void QdMeta::begin_meta_generation() {
  const auto t = static_cast<std::uint64_t>(meta_generation_);
  const auto lambda = params_.meta_population;
  Rng cma_rng = Rng::stream(seed_, {key(StreamKey::kMetaSampling), t});
  const Eigen::MatrixXd& samples = cma_.ask(cma_rng);
  std::vector<const NeuralFeatureMap*> map_ptrs;
  std::vector<GridArchive*> archive_ptrs;
  for (Index i = 0; i < lambda; ++i) {
    const Eigen::VectorXd w = samples.col(i);
    maps_[static_cast<std::size_t>(i)] =
        std::make_unique<NeuralFeatureMap>(shape_, std::span<const double>(w.data(), static_cast<std::size_t>(w.size())));
    map_ptrs.push_back(maps_[static_cast<std::size_t>(i)].get());
    archive_ptrs.push_back(&archives_[static_cast<std::size_t>(i)]);
  }
  rebuild_archives(database_, map_ptrs, archive_ptrs);

  // One number of generations for the whole meta-population.
  Rng control_rng = Rng::stream(seed_, {key(StreamKey::kControl), t});
  // The controller sees the evaluated meta-population only (the authors' realisation of
  // lambda = 1 samples more candidates than it evaluates).
  const int generations = samples.cols() == lambda
                              ? controller_->choose_generations(samples, control_rng)
                              : controller_->choose_generations(Eigen::MatrixXd(samples.leftCols(lambda)), control_rng);
  if (generations < 1) throw Error(fmt::format("controller '{}' chose {} generations", controller_->name(), generations));
  generations_ = generations;
  next_generation_ = 0;
  for (std::size_t m = 0; m < schedulers_.size(); ++m) {  // kCmaMae: each map's emitters, from its own stream
    Rng rng = Rng::stream(seed_, {key(StreamKey::kEmitterStart), t, static_cast<std::uint64_t>(m)});
    schedulers_[m] = start_map_emitters(archives_[m], params_.emitters, rng);
  }
  const Index n = task_.genotype_size();
  const Index batch = params_.batch_size;
  for (std::size_t m = 0; m < static_cast<std::size_t>(lambda); ++m) {
    offspring_[m].resize(generations * batch, n);
    evaluations_[m].resize(generations * batch, task_.base_feature_size());
    blocks_[m].resize(batch, n);
    block_evaluations_[m].resize(batch, task_.base_feature_size());
  }
  phase_ = Phase::kGenerations;
}

// Generation g of map i, from its own stream (seed, variation, t, map, g): its emitters' batch,
// or offspring of its elites (random genotypes while it is empty).
void QdMeta::vary_map(Index i, int g) {
  const auto m = static_cast<std::size_t>(i);
  Rng rng = Rng::stream(seed_, {key(StreamKey::kVariation), static_cast<std::uint64_t>(meta_generation_),
                                static_cast<std::uint64_t>(i), static_cast<std::uint64_t>(g)});
  if (!schedulers_.empty()) blocks_[m] = schedulers_[m]->ask(rng);
  else if (archives_[m].empty()) random_genotypes(blocks_[m], rng);
  else generate_offspring(archives_[m], mutation_, rng, blocks_[m]);
}

// Map i's meta-objective plan (an empty archive scores 0 without one). The objective runs in
// parallel over maps only for a shareable task, as its evaluations did before ask/tell.
void QdMeta::plan_map(Index i) {
  const auto m = static_cast<std::size_t>(i);
  const Index n = task_.genotype_size();
  const GridArchive& archive = archives_[m];
  planned_[m] = 0;
  meta_results_[m] = {};
  if (archive.empty()) return;
  Elites& elites = elites_[m];
  const Index count = archive.size(), dims = archive.dimensions(), nb = archive.base_feature_size();
  elites.genotypes.resize(count, n);
  elites.fitness.resize(count);
  elites.measures.resize(count, dims);
  elites.base_features.resize(count, nb);
  Index row = 0;
  for (Index cell : archive.filled_cells()) {
    std::copy_n(archive.solution(cell), n, elites.genotypes.row(row).data());
    elites.fitness[row] = archive.objective(cell);
    std::copy_n(archive.measures(cell), dims, elites.measures.row(row).data());
    std::copy_n(archive.base_features(cell), nb, elites.base_features.row(row).data());
    ++row;
  }
  Rng rng = Rng::stream(seed_, {key(StreamKey::kMetaFitness), static_cast<std::uint64_t>(meta_generation_),
                                static_cast<std::uint64_t>(i)});
  plans_[m] = meta_objective_->plan(elites.view(), rng);
  check_meta_plan(*meta_objective_, plans_[m], meta_tasks_);
  meta_evaluations_[m].resize(plans_[m].batches.size());
  for (std::size_t k = 0; k < plans_[m].batches.size(); ++k) {
    const MetaBatch& b = plans_[m].batches[k];
    meta_evaluations_[m][k].resize(b.genotypes.rows(), meta_tasks_[static_cast<std::size_t>(b.task)].base_feature_size());
  }
  planned_[m] = 1;
}

bool QdMeta::meta_objective_simulates() const {
  for (std::size_t m = 0; m < planned_.size(); ++m)
    if (planned_[m] && !plans_[m].batches.empty()) return true;
  return false;
}

void QdMeta::score_meta_fitness() {
  for_each_map(params_.meta_population, task_.shareable(), [&](Index i) {
    const auto m = static_cast<std::size_t>(i);
    if (!planned_[m]) return;
    const MetaFitnessResult result = meta_objective_->score(elites_[m].view(), plans_[m], meta_evaluations_[m]);
    if (!std::isfinite(result.value))
      throw Error(fmt::format("meta-objective '{}' returned {} for map {} of meta-generation {}", meta_objective_->name(),
                              result.value, i, meta_generation_ + 1));
    meta_results_[m] = result;
  });
}

void QdMeta::store(const RowMatrix& genotypes, const EvaluationBatch& evaluations) {
  if (params_.database_inputs == DatabaseInputs::kBaseFeatures) {
    database_.insert_valid(genotypes, evaluations);
    return;
  }
  // The authors' set_b(): -1 + 2 b in single precision, for the database only.
  EvaluationBatch shifted = evaluations;
  Real* b = shifted.base_features.data();
  for (Index i = 0; i < shifted.base_features.size(); ++i) b[i] = Real{-1} + Real{2} * b[i];
  database_.insert_valid(genotypes, shifted);
}

void QdMeta::finish_meta_generation() {
  const auto lambda = params_.meta_population;
  std::int64_t bottom_spent = 0, meta_spent = 0;  // this meta-generation's evaluations
  // The database takes every new solution in a fixed order (map by map, oldest first).
  for (Index i = 0; i < lambda; ++i) {
    const auto m = static_cast<std::size_t>(i);
    store(offspring_[m], evaluations_[m]);
    bottom_spent += offspring_[m].rows();
    meta_spent += meta_results_[m].evaluations;
    meta_fitness_[m] = meta_results_[m].value;
  }

  // CMA-ES and the controller learn from the meta-fitness.
  cma_.tell(Eigen::Map<const Eigen::VectorXd>(meta_fitness_.data(), lambda), CmaObjective::kMaximise);
  // Algorithm::tell() counts the offspring (the last generation's once this returns); the
  // meta-objective reports its own.
  count_meta_evaluations(meta_spent);
  const std::int64_t spent = params_.count_meta_evaluations ? bottom_spent + meta_spent : bottom_spent;
  controller_->observe(meta_fitness_, spent);

  // Keep the best map of this meta-generation (first on ties) for the logs and archive.csv.
  const auto best = static_cast<std::size_t>(std::max_element(meta_fitness_.begin(), meta_fitness_.end()) -
                                             meta_fitness_.begin());
  best_archive_ = archives_[best];
  ++meta_generation_;
  const double mean = std::accumulate(meta_fitness_.begin(), meta_fitness_.end(), 0.0) / static_cast<double>(lambda);
  double sq = 0.0;
  // Fused explicitly: whether the compiler fuses this accumulation depends on the CPU it tunes
  // for, and the SD's last digit in meta.csv with it.
  for (double f : meta_fitness_) sq = std::fma(f - mean, f - mean, sq);
  std::vector<ArchiveStats> map_stats;
  for (const GridArchive& archive : archives_) map_stats.push_back(archive.stats());
  record_ = {meta_generation_, meta_fitness_[best], mean, std::sqrt(sq / static_cast<double>(lambda)), generations_,
             controller_->states(), population_stats(map_stats)};
  for (MetaPlan& plan : plans_) plan = {};  // the sampled genotypes are not needed any more
  phase_ = Phase::kIdle;
}

EliteTable QdMeta::elites() const { return best_archive_.elites(); }


namespace {

// The population statistics in their checkpoint order.
template <class Stats>
auto population_fields(Stats& p) {
  return std::array{&p.num_elites, &p.obj_mean, &p.obj_max, &p.qd_score};
}

}  // namespace

// The per-map archives and feature-maps are rebuilt at the start of every meta-generation, so
// only what outlives a meta-generation is saved.
void QdMeta::save(BinaryWriter& out) const {
  require_between_steps("save()");
  out.tag("qd_meta");
  out.value(meta_generation_);
  save_counters(out, counters());
  cma_.save(out);
  database_.save(out);
  best_archive_.save(out);
  out.values(meta_fitness_);
  out.value(record_.meta_generation);
  out.value(record_.meta_fitness_best);
  out.value(record_.meta_fitness_mean);
  out.value(record_.meta_fitness_sd);
  out.value<std::int32_t>(record_.generations);
  out.value(record_.states);
  for (const MeanSe* m : population_fields(record_.population)) {
    out.value(m->mean);
    out.value(m->se);
  }
  controller_->save(out);
}

void QdMeta::load(BinaryReader& in) {
  require_between_steps("load()");
  in.expect_tag("qd_meta");
  meta_generation_ = in.value<std::int64_t>("meta-generation");
  restore_counters(load_counters(in));
  cma_.load(in);
  database_.load(in);
  best_archive_.load(in);
  meta_fitness_ = in.values<double>("meta-fitness");
  if (meta_fitness_.size() != static_cast<std::size_t>(params_.meta_population))
    in.fail(fmt::format("{} meta-fitness values for a meta-population of {}", meta_fitness_.size(),
                        params_.meta_population));
  record_.meta_generation = in.value<std::int64_t>("record meta-generation");
  record_.meta_fitness_best = in.value<double>("record best");
  record_.meta_fitness_mean = in.value<double>("record mean");
  record_.meta_fitness_sd = in.value<double>("record SD");
  record_.generations = in.value<std::int32_t>("record generations");
  record_.states = in.value<std::int64_t>("record states");
  for (MeanSe* m : population_fields(record_.population)) {
    m->mean = in.value<double>("record population mean");
    m->se = in.value<double>("record population SE");
  }
  controller_->load(in);
}

void QdMeta::save_undo(BinaryWriter& out) const {
  out.value(meta_generation_);
  save_counters(out, counters());
  cma_.save(out);
  controller_->save(out);
  out.value(database_.total_inserted());
  if (database_.total_inserted() == 0) database_.save(out);
}

void QdMeta::load_undo(BinaryReader& in) {
  if (in.value<std::int64_t>("meta-generation") != meta_generation_)
    throw Error("qd-meta: the failed step had already finished its meta-generation");
  phase_ = Phase::kIdle;
  next_generation_ = 0;
  restore_counters(load_counters(in));
  cma_.load(in);
  controller_->load(in);
  const auto inserted = in.value<std::int64_t>("database rows inserted");
  if (inserted == 0) database_.load(in);
  else if (database_.total_inserted() != inserted)
    throw Error("qd-meta: the failed step had already changed the database");
}

}  // namespace qdmeta
