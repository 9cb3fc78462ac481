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

EliteTable MapElites::elites() const { return archive_.elites(); }

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
