#include "qdmeta/algorithms/map_elites.hpp"

#include <fmt/format.h>

#include <algorithm>

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

Index insert_batch(GridArchive& archive, const FeatureMap& feature_map, const RowMatrix& genotypes,
                   const EvaluationBatch& evaluations, RowMatrix& targets) {
  const Index count = genotypes.rows();
  targets.resize(count, feature_map.output_size());
  feature_map.map(evaluations.base_features.data(), count, targets.data());
  const bool keep_base = archive.params().base_feature_size > 0;
  Index added = 0;
  for (Index r = 0; r < count; ++r) {
    if (!evaluations.valid[static_cast<std::size_t>(r)]) continue;
    const AddStatus s = archive.add(genotypes.row(r).data(), evaluations.fitness[r], targets.row(r).data(),
                                    keep_base ? evaluations.base_features.row(r).data() : nullptr);
    added += s != AddStatus::kNotAdded;
  }
  return added;
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

void MapElites::step(Evaluator& evaluator) {
  const Index n = task_.genotype_size();
  next_genotypes(archive_, params_, mutation_, seed_, generation_, n, genotypes_);
  evaluations_.resize(genotypes_.rows(), task_.base_feature_size());
  evaluator.evaluate(task_, {genotypes_.data(), genotypes_.rows(), n}, evaluations_.view());
  insert_batch(archive_, *feature_map_, genotypes_, evaluations_, targets_);
  counters_.bottom += genotypes_.rows();
  ++generation_;
}

EliteTable grid_elites(const GridArchive& archive) {
  EliteTable t;
  std::vector<Index> cells = archive.filled_cells();
  std::sort(cells.begin(), cells.end());
  const auto count = static_cast<Index>(cells.size());
  t.index.assign(cells.begin(), cells.end());
  t.objective.resize(cells.size());
  t.measures.resize(count, archive.dimensions());
  t.solutions.resize(count, archive.params().solution_size);
  t.base_features.resize(count, archive.params().base_feature_size);
  for (Index i = 0; i < count; ++i) {
    const Index c = cells[static_cast<std::size_t>(i)];
    t.objective[static_cast<std::size_t>(i)] = archive.objective(c);
    std::copy_n(archive.measures(c), archive.dimensions(), t.measures.row(i).data());
    std::copy_n(archive.solution(c), archive.params().solution_size, t.solutions.row(i).data());
    if (archive.params().base_feature_size > 0)
      std::copy_n(archive.base_features(c), archive.params().base_feature_size, t.base_features.row(i).data());
  }
  return t;
}

EliteTable MapElites::elites() const { return grid_elites(archive_); }

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
  out.tag("map_elites");
  out.value(generation_);
  save_counters(out, counters_);
  archive_.save(out);
}

void MapElites::load(BinaryReader& in) {
  in.expect_tag("map_elites");
  generation_ = in.value<std::int64_t>("generation");
  counters_ = load_counters(in);
  archive_.load(in);
}

}  // namespace qdmeta
