// Tests of src/qdmeta/emitters/gaussian_emitter.{hpp,cpp}: parents, noise and clamping, the
// settings refused (scheduler_test.cpp checks it against MAP-Elites bit for bit).
#include "qdmeta/emitters/gaussian_emitter.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/core/fused.hpp"

namespace qdmeta {
namespace {

GaussianEmitterParams gaussian_params() {
  GaussianEmitterParams p;
  p.x0 = {0.5, 0.5};
  p.sigma = 0.25;
  p.batch_size = 3;
  return p;
}

TEST(GaussianEmitter, AddsNoiseToTheDrawnEliteOrToX0) {
  // An "archive" whose every draw is (10, 20): each row is that plus sigma times the normals, in order.
  const auto elite = [](Rng&, std::vector<double>& genes) {
    genes = {10.0, 20.0};
    return true;
  };
  GaussianEmitter from_elites(gaussian_params(), elite);
  Rng rng(3), expected(3);
  const RowMatrix batch = from_elites.ask(rng);
  for (Index r = 0; r < 3; ++r) {
    EXPECT_EQ(batch(r, 0), static_cast<Real>(fused(0.25, expected.normal(), 10.0)));
    EXPECT_EQ(batch(r, 1), static_cast<Real>(fused(0.25, expected.normal(), 20.0)));
  }
  GaussianEmitter empty_archive(gaussian_params(), [](Rng&, std::vector<double>&) { return false; });
  Rng again(3), normals(3);
  EXPECT_EQ(empty_archive.ask(again)(0, 0), static_cast<Real>(fused(0.25, normals.normal(), 0.5)));
}

TEST(GaussianEmitter, ClampsToFiniteBounds) {
  auto p = gaussian_params();
  p.sigma = 10.0;
  p.batch_size = 50;
  p.lower_bound = 0.0;
  p.upper_bound = 1.0;
  GaussianEmitter e(p, {});
  Rng rng(5);
  const RowMatrix batch = e.ask(rng);
  EXPECT_EQ(batch.minCoeff(), 0.0f);
  EXPECT_EQ(batch.maxCoeff(), 1.0f);
}

TEST(GaussianEmitter, RefusesBadSettingsNamingTheKey) {
  auto p = gaussian_params();
  p.sigma = 0.0;
  EXPECT_INPUT_ERROR(p.validate(), "emitters.sigma = 0 is out of range: must be a positive number");
  p = gaussian_params();
  p.batch_size = 0;
  EXPECT_INPUT_ERROR(GaussianEmitter(p, {}), "emitters.batch_size = 0 is out of range: must be in [1, 1000000]");
  p = gaussian_params();
  p.x0.clear();
  EXPECT_INPUT_ERROR(p.validate(), "GaussianEmitterParams.x0 is empty: give the first parent, one value per gene");
  p = gaussian_params();
  p.lower_bound = 1.0;
  p.upper_bound = 1.0;
  EXPECT_INPUT_ERROR(p.validate(), "GaussianEmitterParams.upper_bound = 1 is invalid: must be > lower_bound = 1");
  GaussianEmitter e(gaussian_params(), {});
  Rng rng(1);
  e.ask(rng);
  EXPECT_INPUT_ERROR(e.ask(rng), "GaussianEmitter::ask: called twice without tell; tell the last batch's outcomes first");
}

}  // namespace
}  // namespace qdmeta
