#pragma once
// Unseen test functions for the test phase (`qdmeta adapt`): a family of changed conditions
// (Rastrigin with dimensions replaced by noise, translated Rastrigin, a damaged robot ...) under
// which an archive's solutions are scored. Higher is better.
#include <span>
#include <string>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

class Evaluator;

class AdaptationTests {
 public:
  virtual ~AdaptationTests() = default;
  virtual std::string name() const = 0;
  virtual Index count() const = 0;
  // Evaluations per test function when the user gives no budget (Rastrigin 100, RHex 50).
  virtual Index default_budget() const { return 100; }
  // The logged score of each row of `genotypes` on test function `test` (0 <= test < count()).
  // `evaluator` runs any simulations the tests need.
  virtual void score(Index test, const RowMatrix& genotypes, Evaluator& evaluator, std::span<double> out) const = 0;
};

}  // namespace qdmeta
