#pragma once
// The RHex test phase (paper section "Experiment setup"; docs/specification.md, Test phase): a family of
// environments (damaged legs or obstacle courses) in which archive controllers are scored by
// their forward distance, dead = 0. The families are the complements of the training sets that
// the Damage and Obstacle meta-fitnesses draw per replicate, so every condition of a replicate
// (QD-Meta or baseline) meets the same unseen environments.
#include <string>
#include <vector>

#include "qdmeta/core/adaptation_tests.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta {

class RhexAdaptationTests final : public AdaptationTests {
 public:
  // `task`'s own environment is ignored: test t walks in environments[t].
  RhexAdaptationTests(std::string name, RhexTask task, std::vector<rhex::RhexEnvironment> environments);
  std::string name() const override { return name_; }
  Index count() const override { return static_cast<Index>(environments_.size()); }
  Index default_budget() const override { return 50; }  // docs/specification.md, Test phase
  // One episode per row, run through evaluator.parallel_for; score = forward distance (m), dead = 0.
  void score(Index test, const RowMatrix& genotypes, Evaluator& evaluator, std::span<double> out) const override;
  const std::vector<rhex::RhexEnvironment>& environments() const { return environments_; }

 private:
  std::string name_;
  RhexTask task_;
  std::vector<rhex::RhexEnvironment> environments_;
};

// Every damage type that is not in `trained`, on each of the 6 legs (type-major, types in the
// paper's order 1..4).
std::vector<rhex::RhexEnvironment> untrained_damage_environments(const std::vector<rhex::RhexEnvironment>& trained);
// Every course 1..9 that is not in `trained`, in course order.
std::vector<rhex::RhexEnvironment> untrained_course_environments(const std::vector<rhex::RhexEnvironment>& trained);

}  // namespace qdmeta
