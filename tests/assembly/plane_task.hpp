#pragma once
// The task the RunParts tests hand over as a value: one no registry knows, of `genes` genes;
// fitness minus the sum of the genes, base features the first two genes.
#include <string>

#include "qdmeta/core/task.hpp"

namespace qdmeta::test {

struct Plane {
  Index genes = 3;
  std::string name() const { return "plane"; }
  Index genotype_size() const { return genes; }
  Index base_feature_size() const { return 2; }
  void evaluate(GenotypeView g, EvaluationView out) const {
    for (Index i = 0; i < g.count; ++i) {
      out.fitness[i] = 0;
      for (Index k = 0; k < genes; ++k) out.fitness[i] -= g.row(i)[k];
      out.base_row(i)[0] = g.row(i)[0];
      out.base_row(i)[1] = g.row(i)[1];
      out.valid[i] = 1;
    }
  }
};

}  // namespace qdmeta::test
