#pragma once
// Dynamic parameter control of QD-Meta: how many MAP-Elites generations each meta-generation
// runs (one G shared by all maps of the meta-generation). The static controller fixes G; the
// SARSA(lambda) controller learns it (docs/specification.md, SARSA(lambda) control).
#include <cstdint>
#include <span>
#include <string>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/eigen.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {

class GenerationController {
 public:
  virtual ~GenerationController() = default;
  virtual std::string name() const = 0;
  // At the start of a meta-generation, after CMA-ES sampled it: `samples` holds the new
  // meta-genotypes as columns. Returns G >= 1.
  virtual int choose_generations(const Eigen::MatrixXd& samples, Rng& rng) = 0;
  // The largest G choose_generations() may return (QD-Meta sizes its offspring buffers by it).
  virtual int max_generations() const = 0;
  // After the meta-generation: each map's meta-fitness, and the evaluations it spent (counted
  // as the budget counts them).
  virtual void observe(std::span<const double> meta_fitness, std::int64_t evaluations) = 0;
  // Number of discrete states (1 for the static controller), logged in meta.csv.
  virtual std::int64_t states() const { return 1; }
  // Checkpoints: everything the controller has learnt, so a resumed run acts as it would have.
  virtual void save(BinaryWriter& out) const = 0;
  virtual void load(BinaryReader& in) = 0;
};

class StaticControl final : public GenerationController {
 public:
  // The config parameter its constructor checks (core/params.hpp).
  static constexpr IntParam kGenerations{"control", "generations", 1, 1'000'000, "G for the static controller"};
  explicit StaticControl(int generations);  // throws InputError unless >= 1
  std::string name() const override { return "static"; }
  int choose_generations(const Eigen::MatrixXd&, Rng&) override { return generations_; }
  int max_generations() const override { return generations_; }
  void observe(std::span<const double>, std::int64_t) override {}
  void save(BinaryWriter& out) const override { out.tag("static_control"); }
  void load(BinaryReader& in) override { in.expect_tag("static_control"); }

 private:
  int generations_;
};

}  // namespace qdmeta
