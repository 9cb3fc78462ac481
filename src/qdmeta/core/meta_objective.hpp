#pragma once
// A meta-objective scores a whole archive (QD-Meta's meta-fitness): e.g. its performance under
// perturbed Rastrigin functions, or a robot's archive under damages. Higher is better.
//
// Two phases, so that QD-Meta can hand the simulations to its ask/tell requests:
//   plan(elites, rng)                 draws everything random and lists the batches to simulate
//                                     (each: an index into tasks() and its genotypes), plus any
//                                     state the objective wants back; an analytic objective
//                                     computes its result here and lists no batches;
//   score(elites, plan, results)      the meta-fitness from the batches' evaluations, one
//                                     EvaluationBatch per plan batch, in plan order.
// evaluate(elites, rng, evaluator) runs both with the evaluator in between. plan() and score()
// are const and must be safe to call concurrently for different archives (QD-Meta scores its
// maps in parallel when its task is shareable).
#include <any>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

class Evaluator;

struct MetaFitnessResult {
  double value = 0.0;            // the meta-fitness
  std::int64_t evaluations = 0;  // solution x task evaluations spent computing it
};

// One batch a meta-objective needs simulated: `genotypes` (one per row) through tasks()[task].
struct MetaBatch {
  Index task = 0;
  RowMatrix genotypes;
};

struct MetaPlan {
  std::vector<MetaBatch> batches;  // may be empty: nothing to simulate
  std::any state;                  // whatever score() needs back (e.g. the sample, or the result)
};

class MetaObjective {
 public:
  virtual ~MetaObjective() = default;
  virtual std::string name() const = 0;
  // `elites`: the archive's genotypes, one per row (any order). `rng`: this evaluation's own
  // stream (sampling, perturbations), used by plan() only.
  virtual MetaPlan plan(const RowMatrix& elites, Rng& rng) const = 0;
  // `results[k]`: the evaluations of plan.batches[k] by tasks()[plan.batches[k].task].
  virtual MetaFitnessResult score(const RowMatrix& elites, const MetaPlan& plan,
                                  std::span<const EvaluationBatch> results) const = 0;
  // plan, the batches as one evaluate_jobs request, score. Throws Error naming the objective
  // when a batch names no task of tasks() or has the wrong number of genes.
  MetaFitnessResult evaluate(const RowMatrix& elites, Rng& rng, Evaluator& evaluator) const;
  // The tasks plan()'s batches refer to (e.g. one per environment), in a fixed order. A
  // distributed evaluator ships only an index into this list, so every rank, building the
  // objective from the same config, must list the same tasks.
  virtual std::vector<Task> tasks() const { return {}; }
};

// Checks a plan against `tasks` (the objective's tasks()): every batch names one of them and has
// its genotype size. Throws Error naming the objective and the batch.
void check_meta_plan(const MetaObjective& objective, const MetaPlan& plan, std::span<const Task> tasks);

}  // namespace qdmeta
