#pragma once
// A meta-objective scores a whole archive (QD-Meta's meta-fitness): e.g. its performance under
// perturbed Rastrigin functions, or a robot's archive under damages. Higher is better.
//
// Two phases, so that QD-Meta can hand the simulations to its ask/tell requests:
//   plan(archive, rng)                draws everything random and lists the batches to simulate
//                                     (each: an index into tasks() and its genotypes), plus any
//                                     state the objective wants back; an analytic objective
//                                     computes its result here and lists no batches;
//   score(archive, plan, results)     the meta-fitness from the batches' evaluations, one
//                                     EvaluationBatch per plan batch, in plan order.
// evaluate(archive, rng, evaluator) runs both with the evaluator in between. plan() and score()
// are const and must be safe to call concurrently for different archives (QD-Meta scores its
// maps in parallel when its task is shareable). The archive is its elites' genotypes and, from
// QD-Meta, what the archive stored for each (MetaArchive): an objective that needs an elite's
// fitness or measures reads them there instead of evaluating the elite again.
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

// The archive a meta-objective scores: one elite per row of each matrix, in the same (any) order.
// QD-Meta hands over everything its archive stored: the genotype, the fitness, the measures (the
// feature-map's output, the cell's descriptor) and the task's base features the measures came
// from. An archive made from genotypes alone (the implicit conversion, for tests and for
// evaluating a plain set of solutions) has none of the stored values: has_stored() is false and
// their accessors throw Error.
class MetaArchive {
 public:
  MetaArchive(const RowMatrix& genotypes) : genotypes_(&genotypes) {}  // NOLINT: implicit on purpose
  // Throws Error when the row counts differ.
  MetaArchive(const RowMatrix& genotypes, const Vector& fitness, const RowMatrix& measures,
              const RowMatrix& base_features);
  Index size() const { return genotypes_->rows(); }
  const RowMatrix& genotypes() const { return *genotypes_; }
  bool has_stored() const { return fitness_ != nullptr; }
  const Vector& fitness() const;          // the fitness the archive stored
  const RowMatrix& measures() const;      // in [0, 1]^measure_size
  const RowMatrix& base_features() const;

 private:
  const RowMatrix* genotypes_;
  const Vector* fitness_ = nullptr;
  const RowMatrix* measures_ = nullptr;
  const RowMatrix* base_features_ = nullptr;
};

struct MetaPlan {
  std::vector<MetaBatch> batches;  // may be empty: nothing to simulate
  std::any state;                  // whatever score() needs back (e.g. the sample, or the result)
};

class MetaObjective {
 public:
  virtual ~MetaObjective() = default;
  virtual std::string name() const = 0;
  // `archive`: the elites to score. `rng`: this evaluation's own stream (sampling,
  // perturbations), used by plan() only.
  virtual MetaPlan plan(const MetaArchive& archive, Rng& rng) const = 0;
  // `results[k]`: the evaluations of plan.batches[k] by tasks()[plan.batches[k].task].
  virtual MetaFitnessResult score(const MetaArchive& archive, const MetaPlan& plan,
                                  std::span<const EvaluationBatch> results) const = 0;
  // plan, the batches as one evaluate_jobs request, score. Throws Error naming the objective
  // when a batch names no task of tasks() or has the wrong number of genes.
  MetaFitnessResult evaluate(const MetaArchive& archive, Rng& rng, Evaluator& evaluator) const;
  // The tasks plan()'s batches refer to (e.g. one per environment), in a fixed order. A
  // distributed evaluator ships only an index into this list, so every rank, building the
  // objective from the same config, must list the same tasks.
  virtual std::vector<Task> tasks() const { return {}; }
};

// Checks a plan against `tasks` (the objective's tasks()): every batch names one of them and has
// its genotype size. Throws Error naming the objective and the batch.
void check_meta_plan(const MetaObjective& objective, const MetaPlan& plan, std::span<const Task> tasks);

}  // namespace qdmeta
