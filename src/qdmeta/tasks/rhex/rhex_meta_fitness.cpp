#include "qdmeta/tasks/rhex/rhex_meta_fitness.hpp"

#include <fmt/format.h>

#include <utility>

#include "qdmeta/core/error.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"  // meta_sample_size, sample_elites

namespace qdmeta {

void RhexMetaParams::validate() const {
  require(kSampleFraction, sample_fraction);
}

RhexMetaFitness::RhexMetaFitness(std::string name, RhexMetaParams params, RhexTask task,
                                 std::vector<rhex::RhexEnvironment> environments)
    : name_(std::move(name)), params_(params), environments_(std::move(environments)) {
  params_.validate();
  if (environments_.empty()) throw InputError(fmt::format("{}: needs at least one environment", name_));
  for (const auto& e : environments_) {
    e.validate();
    RhexParams p = task.params();
    p.environment = e;
    env_tasks_.emplace_back(RhexTask(p));
  }
}

MetaPlan RhexMetaFitness::plan(const MetaArchive& archive, Rng& rng) const {
  const RowMatrix& elites = archive.genotypes();
  MetaPlan plan;
  const Index n = meta_sample_size(params_.sample_fraction, elites.rows());
  if (n == 0) return plan;
  const std::vector<Index> sample = sample_elites(elites.rows(), n, rng);
  RowMatrix sampled(n, elites.cols());
  for (Index s = 0; s < n; ++s) sampled.row(s) = elites.row(sample[static_cast<std::size_t>(s)]);
  const auto env_count = static_cast<Index>(environments_.size());
  for (Index e = 0; e < env_count; ++e) plan.batches.push_back({e, sampled});
  return plan;
}

MetaFitnessResult RhexMetaFitness::score(const MetaArchive& /*archive*/, const MetaPlan& plan,
                                         std::span<const EvaluationBatch> results) const {
  if (plan.batches.empty()) return {};
  const auto env_count = static_cast<Index>(environments_.size());
  const Index n = plan.batches.front().genotypes.rows();
  if (results.size() != plan.batches.size() || plan.batches.size() != environments_.size())
    throw Error(fmt::format("{}: score() got {} result blocks for a plan of {} batches over {} environments", name_,
                            results.size(), plan.batches.size(), environments_.size()));
  for (const EvaluationBatch& r : results)
    if (r.size() != n) throw Error(fmt::format("{}: score() got a block of {} rows for {} sampled solutions", name_, r.size(), n));
  // Solution-major, as the episodes are listed: the sum's order is fixed.
  double sum = 0.0;
  for (Index s = 0; s < n; ++s)
    for (Index e = 0; e < env_count; ++e) {
      const EvaluationBatch& r = results[static_cast<std::size_t>(e)];
      sum += r.valid[static_cast<std::size_t>(s)] ? static_cast<double>(r.fitness[s]) : 0.0;
    }
  return {sum / static_cast<double>(n * env_count), n * env_count};
}

std::vector<rhex::DamageType> draw_damage_types(Rng& rng, int types) {
  std::vector<rhex::DamageType> all{rhex::DamageType::kLegRemoval, rhex::DamageType::kLegShortening,
                                    rhex::DamageType::kBlockedHip, rhex::DamageType::kPassiveHip};
  choose_without_replacement(all, static_cast<std::size_t>(types), rng);
  return all;
}

std::vector<rhex::RhexEnvironment> damage_environments(const std::vector<rhex::DamageType>& types) {
  std::vector<rhex::RhexEnvironment> envs;
  for (rhex::DamageType t : types)
    for (int leg = 0; leg < rhex::kLegs; ++leg) envs.push_back(rhex::RhexEnvironment::damaged(t, leg));
  return envs;
}

std::vector<rhex::ObstacleCourse> draw_courses(Rng& rng, int count) {
  std::vector<rhex::ObstacleCourse> all;
  for (int c = 1; c <= 9; ++c) all.push_back(static_cast<rhex::ObstacleCourse>(c));
  choose_without_replacement(all, static_cast<std::size_t>(count), rng);
  return all;
}

}  // namespace qdmeta
