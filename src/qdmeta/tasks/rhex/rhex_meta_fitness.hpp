#pragma once
// QD-Meta's RHex meta-fitnesses (paper eqs. meta-damage and meta-obstacle, docs/specification.md, Meta-objectives):
// the mean forward distance of a sample of the archive (by default all of it) over a set of
// environments, dead = 0. Damage: 2 damage types drawn per replicate x 6 legs; Obstacle: 5 of
// the 9 courses drawn per replicate. Higher is better.
//
// Random draws, all from the `rng` given to plan() (or evaluate()): the sample only,
// sample_elites(elites.rows(), meta_sample_size(fraction, elites.rows()), rng); with the default
// fraction 1 that is a permutation of the whole archive (its order does not change the result).
#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/core/meta_objective.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta {

struct RhexMetaParams {
  static constexpr RealParam kSampleFraction{"meta_fitness", "sample_fraction", 0.0, 1.0, Open::kLower,
                                             "fraction of the archive scored (the authors' RHex runs: all of it)"};
  double sample_fraction = 1.0;  // share of the archive scored (kSampleFraction)
  void validate() const;
};

class RhexMetaFitness final : public MetaObjective {
 public:
  // `name`: "rhex-damage" or "rhex-obstacle"; `environments`: where each sampled solution walks.
  RhexMetaFitness(std::string name, RhexMetaParams params, RhexTask task, std::vector<rhex::RhexEnvironment> environments);
  std::string name() const override { return name_; }
  // F = (1 / (n E)) sum_s sum_e f(g_s; e), dead = 0; evaluations = n E. plan() lists one batch
  // per environment (the n sampled genotypes; QD-Meta sends them as one request, so MPI ranks
  // can share them); score() sums the episodes in a fixed order (solution-major), so F does not
  // depend on the threads or ranks. f is the task's fitness (Real, float), as stored in archives.
  MetaPlan plan(const MetaArchive& archive, Rng& rng) const override;
  MetaFitnessResult score(const MetaArchive& archive, const MetaPlan& plan,
                          std::span<const EvaluationBatch> results) const override;
  // One RHex task per environment, in environments() order.
  std::vector<Task> tasks() const override { return env_tasks_; }
  const std::vector<rhex::RhexEnvironment>& environments() const { return environments_; }

 private:
  std::string name_;
  RhexMetaParams params_;
  std::vector<rhex::RhexEnvironment> environments_;
  std::vector<Task> env_tasks_;
};

// The paper's training sets, drawn once per replicate from `rng`.
// Damage: `types` of the 4 damage types (without replacement), each on legs 0..5, type-major.
std::vector<rhex::DamageType> draw_damage_types(Rng& rng, int types = 2);
std::vector<rhex::RhexEnvironment> damage_environments(const std::vector<rhex::DamageType>& types);
// Obstacle: `count` of the 9 courses (without replacement), in draw order.
std::vector<rhex::ObstacleCourse> draw_courses(Rng& rng, int count = 5);

}  // namespace qdmeta
