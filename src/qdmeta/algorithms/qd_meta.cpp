#include "qdmeta/algorithms/qd_meta.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/meta/rebuild.hpp"

namespace qdmeta {

void QdMetaParams::validate() const {
  require_range("qd_meta.meta_population", meta_population, Index{1}, Index{10'000});
  require_range("qd_meta.batch_size", batch_size, Index{1}, Index{10'000'000});
  require_range("qd_meta.initial_population", initial_population, Index{1}, Index{100'000'000});
  require_range("qd_meta.database_capacity", database_capacity, Index{1}, Index{1'000'000'000});
  require_range("qd_meta.hidden", hidden, Index{1}, Index{10'000});
  if (!(sigmoid_scale > 0 && std::isfinite(sigmoid_scale)))
    throw InputError(fmt::format("qd_meta.sigmoid_scale = {} is out of range: must be a positive number", sigmoid_scale));
  if (!(cma_sigma > 0 && std::isfinite(cma_sigma)))
    throw InputError(fmt::format("cma_es.sigma = {} is out of range: must be a positive number", cma_sigma));
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
  return c;
}

}  // namespace

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
  archives_.assign(lambda, best_archive_);
  maps_.resize(lambda);
  offspring_.resize(lambda);
  evaluations_.resize(lambda);
  meta_results_.resize(lambda);
  meta_fitness_.resize(lambda);
}

void QdMeta::seed_database(Evaluator& evaluator) {
  RowMatrix genotypes(params_.initial_population, task_.genotype_size());
  Rng rng = Rng::stream(seed_, {key(StreamKey::kInitialPopulation)});
  random_genotypes(genotypes, rng);
  EvaluationBatch batch;
  batch.resize(genotypes.rows(), task_.base_feature_size());
  evaluator.evaluate(task_, {genotypes.data(), genotypes.rows(), genotypes.cols()}, batch.view());
  database_.insert_valid(genotypes, batch);
  counters_.bottom += genotypes.rows();
}

// Runs G MAP-Elites generations in map i, keeping every offspring for the database, then
// scores the archive. Touches only map i's buffers and streams, so maps may run in parallel.
void QdMeta::evolve_map(Index i, int generations, Evaluator& evaluator) {
  const auto m = static_cast<std::size_t>(i);
  const Index n = task_.genotype_size();
  const Index batch = params_.batch_size;
  GridArchive& archive = archives_[m];
  RowMatrix& genotypes = offspring_[m];
  EvaluationBatch& evaluations = evaluations_[m];
  genotypes.resize(generations * batch, n);
  evaluations.resize(generations * batch, task_.base_feature_size());
  RowMatrix block(batch, n), targets;
  EvaluationBatch block_evaluations;
  block_evaluations.resize(batch, task_.base_feature_size());
  const auto t = static_cast<std::uint64_t>(meta_generation_);
  for (int g = 0; g < generations; ++g) {
    Rng rng = Rng::stream(seed_, {key(StreamKey::kVariation), t, static_cast<std::uint64_t>(i), static_cast<std::uint64_t>(g)});
    if (archive.empty()) random_genotypes(block, rng);
    else generate_offspring(archive, mutation_, rng, block);
    evaluator.evaluate(task_, {block.data(), batch, n}, block_evaluations.view());
    insert_batch(archive, *maps_[m], block, block_evaluations, targets);
    genotypes.middleRows(g * batch, batch) = block;
    evaluations.fitness.segment(g * batch, batch) = block_evaluations.fitness;
    evaluations.base_features.middleRows(g * batch, batch) = block_evaluations.base_features;
    std::copy(block_evaluations.valid.begin(), block_evaluations.valid.end(),
              evaluations.valid.begin() + static_cast<std::ptrdiff_t>(g * batch));
  }
  MetaFitnessResult result;
  if (!archive.empty()) {
    RowMatrix elites(archive.size(), n);
    Index row = 0;
    for (Index cell : archive.filled_cells()) std::copy_n(archive.solution(cell), n, elites.row(row++).data());
    Rng rng = Rng::stream(seed_, {key(StreamKey::kMetaFitness), t, static_cast<std::uint64_t>(i)});
    result = meta_objective_->evaluate(elites, rng, evaluator);
    if (!std::isfinite(result.value))
      throw Error(fmt::format("meta-objective '{}' returned {} for map {} of meta-generation {}", meta_objective_->name(),
                              result.value, i, meta_generation_ + 1));
  }
  meta_results_[m] = result;
}

void QdMeta::step(Evaluator& evaluator) {
  if (meta_generation_ == 0 && database_.total_inserted() == 0 && counters_.bottom == 0) seed_database(evaluator);
  const EvaluationCounters before = counters_;
  const auto t = static_cast<std::uint64_t>(meta_generation_);
  const auto lambda = params_.meta_population;

  // 1. Sample the meta-population and rebuild every map from the whole database.
  Rng cma_rng = Rng::stream(seed_, {key(StreamKey::kMetaSampling), t});
  const Eigen::MatrixXd& samples = cma_.ask([&cma_rng] { return cma_rng.normal(); });
  std::vector<const NeuralFeatureMap*> map_ptrs;
  std::vector<GridArchive*> archive_ptrs;
  for (Index i = 0; i < lambda; ++i) {
    const Eigen::VectorXd w = samples.col(i);
    maps_[static_cast<std::size_t>(i)] =
        std::make_unique<NeuralFeatureMap>(shape_, std::span<const double>(w.data(), static_cast<std::size_t>(w.size())));
    map_ptrs.push_back(maps_[static_cast<std::size_t>(i)].get());
    archive_ptrs.push_back(&archives_[static_cast<std::size_t>(i)]);
  }
  evaluator.within_workers([&] { rebuild_archives(database_, map_ptrs, archive_ptrs); });

  // 2. One number of generations for the whole meta-population.
  Rng control_rng = Rng::stream(seed_, {key(StreamKey::kControl), t});
  const int generations = controller_->choose_generations(samples, control_rng);
  if (generations < 1) throw Error(fmt::format("controller '{}' chose {} generations", controller_->name(), generations));

  // 3. Evolve and score each map. A shareable task lets maps run in parallel, each evaluating
  // serially; otherwise maps run in turn and the evaluator parallelises each batch.
  if (task_.shareable()) {
    evaluator.parallel_for(lambda, [&](Index i) {
      SerialEvaluator serial;
      evolve_map(i, generations, serial);
    });
  } else {
    for (Index i = 0; i < lambda; ++i) evolve_map(i, generations, evaluator);
  }

  // 4. The database takes every new solution in a fixed order (map by map, oldest first).
  for (Index i = 0; i < lambda; ++i) {
    const auto m = static_cast<std::size_t>(i);
    database_.insert_valid(offspring_[m], evaluations_[m]);
    counters_.bottom += offspring_[m].rows();
    counters_.meta += meta_results_[m].evaluations;
    meta_fitness_[m] = meta_results_[m].value;
  }

  // 5. CMA-ES and the controller learn from the meta-fitness.
  cma_.tell(Eigen::Map<const Eigen::VectorXd>(meta_fitness_.data(), lambda), CmaObjective::kMaximise);
  const std::int64_t spent = params_.count_meta_evaluations ? counters_.total() - before.total()
                                                            : counters_.bottom - before.bottom;
  controller_->observe(meta_fitness_, spent);

  // 6. Keep the best map of this meta-generation (first on ties) for the logs and archive.csv.
  const auto best = static_cast<std::size_t>(std::max_element(meta_fitness_.begin(), meta_fitness_.end()) -
                                             meta_fitness_.begin());
  best_archive_ = archives_[best];
  ++meta_generation_;
  const double mean = std::accumulate(meta_fitness_.begin(), meta_fitness_.end(), 0.0) / static_cast<double>(lambda);
  double sq = 0.0;
  for (double f : meta_fitness_) sq += (f - mean) * (f - mean);
  record_ = {meta_generation_, meta_fitness_[best], mean, std::sqrt(sq / static_cast<double>(lambda)), generations,
             controller_->states()};
}

EliteTable QdMeta::elites() const { return best_archive_.elites(); }


// The per-map archives and feature-maps are rebuilt at the start of every meta-generation, so
// only what outlives a meta-generation is saved.
void QdMeta::save(BinaryWriter& out) const {
  out.tag("qd_meta");
  out.value(meta_generation_);
  save_counters(out, counters_);
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
  controller_->save(out);
}

void QdMeta::load(BinaryReader& in) {
  in.expect_tag("qd_meta");
  meta_generation_ = in.value<std::int64_t>("meta-generation");
  counters_ = load_counters(in);
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
  controller_->load(in);
}

}  // namespace qdmeta
