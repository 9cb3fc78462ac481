#pragma once
// Random search, the baseline of quality-diversity: every generation evaluates genotypes drawn
// uniformly from [0, 1]^n and adds them to a grid archive through a feature-map. It is MAP-Elites
// without selection and variation, so what MAP-Elites finds beyond it is what they are worth.
// `algorithm = "random-search"` in arm-qd's configs, with MAP-Elites's tables.
#include <qdmeta/algorithms/algorithm.hpp>
#include <qdmeta/algorithms/map_elites.hpp>
#include <qdmeta/archive/grid_archive.hpp>
#include <qdmeta/featuremap/feature_map.hpp>
#include <qdmeta/plugin/algorithm_builder.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace arm {

class RandomSearch final : public qdmeta::Algorithm {
 public:
  // `archive` is complete: its solution_size and qd_offset are the task's.
  RandomSearch(qdmeta::MapElitesParams params, qdmeta::Task task, std::unique_ptr<qdmeta::FeatureMap> feature_map,
               qdmeta::GridArchiveParams archive, std::uint64_t seed);

  std::string name() const override { return "random-search"; }
  std::int64_t generation() const override { return generation_; }
  qdmeta::ArchiveStats stats() const override { return archive_.stats(); }
  qdmeta::EliteTable elites() const override { return archive_.elites(); }

  // The generation, the counters and the archive are the whole state: a generation's genotypes
  // come from the stream of (seed, generation), so no generator is saved.
  bool checkpointable() const override { return true; }
  void save(qdmeta::BinaryWriter& out) const override;
  void load(qdmeta::BinaryReader& in) override;

 protected:
  // A step is one request: the generation's genotypes, one job.
  void next_request(std::vector<qdmeta::EvaluationJob>& jobs) override;
  // Adds the evaluated genotypes to the archive; the step is then complete.
  bool take_results() override;
  // Only take_results() changes the state, so undoing a failed step is dropping its request.
  void save_undo(qdmeta::BinaryWriter& out) const override { save_generation_undo(out); }
  void load_undo(qdmeta::BinaryReader& in) override { load_generation_undo(in); }

 private:
  qdmeta::MapElitesParams params_;
  qdmeta::Task task_;
  std::unique_ptr<qdmeta::FeatureMap> feature_map_;
  qdmeta::GridArchive archive_;
  std::uint64_t seed_;
  std::int64_t generation_ = 0;
  qdmeta::RowMatrix genotypes_;  // the pending request's genotypes and their evaluations
  qdmeta::EvaluationBatch evaluations_;
  qdmeta::RowMatrix targets_;  // the target features of a batch, insert_batch's scratch
};

// algorithm = "random-search": reads [map_elites] (batch_size, initial_population), [archive]
// (a grid) and [feature_map] as MAP-Elites does; [mutation] is read for every algorithm and
// unused here.
qdmeta::AlgorithmMaker build_random_search(qdmeta::AlgorithmBuild& build);

// Makes `algorithm = "random-search"` available to configs (qdmeta's algorithm registry).
void register_random_search();

}  // namespace arm
