#pragma once
// A meta-objective scores a whole archive (QD-Meta's meta-fitness): e.g. its performance under
// perturbed Rastrigin functions, or a robot's archive under damages. Higher is better.
#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

class Evaluator;

struct MetaFitnessResult {
  double value = 0.0;            // the meta-fitness
  std::int64_t evaluations = 0;  // solution x task evaluations spent computing it
};

class MetaObjective {
 public:
  virtual ~MetaObjective() = default;
  virtual std::string name() const = 0;
  // `elites`: the archive's genotypes, one per row (any order). `rng`: this evaluation's own
  // stream (sampling, perturbations). `evaluator` runs any simulations the objective needs.
  virtual MetaFitnessResult evaluate(const RowMatrix& elites, Rng& rng, Evaluator& evaluator) const = 0;
  // The tasks evaluate() hands to the evaluator (e.g. one per environment), in a fixed order.
  // A distributed evaluator ships only an index into this list, so every rank, building the
  // objective from the same config, must list the same tasks.
  virtual std::vector<Task> tasks() const { return {}; }
};

}  // namespace qdmeta
