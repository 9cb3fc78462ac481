#pragma once
// A feature-map turns base features (what a task measures) into target features (an
// archive's axes), for a whole block of rows at once.
#include "qdmeta/core/types.hpp"

namespace qdmeta {

class FeatureMap {
 public:
  virtual ~FeatureMap() = default;
  virtual Index input_size() const = 0;   // N_b
  virtual Index output_size() const = 0;  // N_t
  // base: count x N_b row-major; target: count x N_t row-major, already sized.
  virtual void map(const Real* base, Index count, Real* target) const = 0;
};

}  // namespace qdmeta
