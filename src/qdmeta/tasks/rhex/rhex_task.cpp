#include "qdmeta/tasks/rhex/rhex_task.hpp"

#include <algorithm>
#include <array>

namespace qdmeta {

void RhexParams::validate() const {
  require(kGeneStep, gene_step);
  episode.validate();
  environment.validate();
}

RhexTask::RhexTask(RhexParams params) : params_(params) { params_.validate(); }

TaskShape RhexTask::shape_of(const RhexParams& p) {
  const Index features = p.features == RhexFeatures::kTrajectory ? rhex::kTrajectoryFeatures : rhex::kFeatureSetFeatures;
  return {"rhex", rhex::kGenes, features, -1.0};
}

Index RhexTask::base_feature_size() const { return shape_of(params_).base_feature_size; }

rhex::GaitParams RhexTask::gait(const Real* genes) const {
  std::array<double, rhex::kGenes> g{};
  for (int i = 0; i < rhex::kGenes; ++i) g[i] = rhex::discretise_gene(genes[i], params_.gene_step);
  return rhex::decode_gait(g.data(), params_.stance_offset);
}

rhex::EpisodeResult RhexTask::episode(const Real* genes, const rhex::RhexEnvironment& environment) const {
  return rhex::run_episode(params_.episode, gait(genes), environment);
}

void RhexTask::base_features(const rhex::EpisodeResult& result, Real* out) const {
  if (params_.features == RhexFeatures::kTrajectory) rhex::trajectory_features(result.trajectory, out);
  else rhex::feature_set_features(result.counts, out);
}

void RhexTask::evaluate(GenotypeView genotypes, EvaluationView out) const {
  for (Index i = 0; i < genotypes.count; ++i) {
    const rhex::EpisodeResult result = episode(genotypes.row(i), params_.environment);
    Real* b = out.base_row(i);
    out.valid[i] = result.dead ? 0 : 1;
    out.fitness[i] = result.dead ? Real{0} : static_cast<Real>(result.fitness);
    if (result.dead) std::fill_n(b, out.base_feature_size, Real{0});
    else base_features(result, b);
  }
}

}  // namespace qdmeta
