#pragma once
// A meta-objective written in Python: a callable taking the map's elites (a (k x genotype_size)
// float32 array, one elite per row; with `archive`, a dict of what the archive stored for them:
// solution, objective, measures, base_features) and an integer seed for its own random draws, returning
// the meta-fitness (higher is better), or (meta-fitness, evaluations spent) when it evaluated
// solutions itself (through its task, say). It runs in plan(): nothing is left for the
// evaluator, so QD-Meta's budget counts only the evaluations it reports.
#include <pybind11/pybind11.h>

#include <string>

#include "python_object.hpp"
#include "qdmeta/core/meta_objective.hpp"

namespace qdmeta::python {

class PythonMetaObjective final : public MetaObjective {
 public:
  PythonMetaObjective(pybind11::object function, std::string name, bool archive);

  std::string name() const override { return name_; }
  // The function; call only with the GIL held.
  const pybind11::object& function() const { return function_.get(); }
  bool reads_archive() const { return archive_; }
  // Takes the GIL; the seed is drawn from `rng`, so the same run gives the function the same seeds.
  MetaPlan plan(const MetaArchive& archive, Rng& rng) const override;
  MetaFitnessResult score(const MetaArchive& archive, const MetaPlan& plan,
                          std::span<const EvaluationBatch> results) const override;

 private:
  SharedPyObject function_;
  std::string name_;
  bool archive_;
};

}  // namespace qdmeta::python
