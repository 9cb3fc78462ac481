#pragma once
// Plain MAP-Elites over a grid archive (docs/specification.md, MAP-Elites): an initial population of random
// genotypes, then generations of `batch_size` offspring, each a mutated copy of a parent drawn
// uniformly from the filled cells; no crossover. Target features come from a FeatureMap.
#include <algorithm>
#include <memory>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/archive/archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/featuremap/feature_map.hpp"

namespace qdmeta {

struct MapElitesParams {
  Index batch_size = 400;          // offspring per generation, >= 1
  Index initial_population = 2000; // random genotypes evaluated first, >= 1
  void validate() const;
};

// Building blocks shared with QD-Meta's per-map evolution and CVT-MAP-Elites.
// Fills `genotypes` (count x n) uniformly at random in [0, 1].
void random_genotypes(RowMatrix& genotypes, Rng& rng);
// Fills `offspring` (rows already sized) with mutated copies of parents, all drawn first:
// pick_parent(rng) returns a pointer to one parent's genes (any archive's selection).
template <class PickParent>
void mutate_copies(PickParent&& pick_parent, const Mutation& mutation, Rng& rng, RowMatrix& offspring) {
  const Index n = offspring.cols();
  for (Index r = 0; r < offspring.rows(); ++r) std::copy_n(pick_parent(rng), n, offspring.row(r).data());
  mutation.apply(offspring, rng);
}

// Fills `offspring` (rows already sized) with mutated copies of uniformly drawn elites of any
// archive (GridArchive, CvtArchive); with `parents`, records each row's parent cell there.
template <EliteArchive Archive>
void generate_offspring(const Archive& archive, const Mutation& mutation, Rng& rng, RowMatrix& offspring,
                        std::vector<Index>* parents = nullptr) {
  const Index n = offspring.cols();
  if (parents) parents->resize(static_cast<std::size_t>(offspring.rows()));
  for (Index r = 0; r < offspring.rows(); ++r) {
    const Index cell = archive.sample_cell(rng);
    std::copy_n(archive.solution(cell), n, offspring.row(r).data());
    if (parents) (*parents)[static_cast<std::size_t>(r)] = cell;
  }
  mutation.apply(offspring, rng);
}

// The candidates of one MAP-Elites generation into `genotypes` (n columns): random genotypes
// while the archive is empty (the initial population in generation 0, a batch after, when every
// solution so far was invalid), else a batch of mutated elites. Each generation has its own
// stream, (seed, kInitialPopulation or kVariation, generation). With `parents`, records each
// row's parent cell there (-1 for random genotypes).
template <EliteArchive Archive>
void next_genotypes(const Archive& archive, const MapElitesParams& params, const Mutation& mutation,
                    std::uint64_t seed, std::int64_t generation, Index n, RowMatrix& genotypes,
                    std::vector<Index>* parents = nullptr) {
  const auto g = static_cast<std::uint64_t>(generation);
  if (archive.empty()) {
    genotypes.resize(generation == 0 ? params.initial_population : params.batch_size, n);
    Rng rng = Rng::stream(seed, {key(StreamKey::kInitialPopulation), g});
    random_genotypes(genotypes, rng);
    if (parents) parents->assign(static_cast<std::size_t>(genotypes.rows()), -1);
  } else {
    genotypes.resize(params.batch_size, n);
    Rng rng = Rng::stream(seed, {key(StreamKey::kVariation), g});
    generate_offspring(archive, mutation, rng, genotypes, parents);
  }
}
// Maps base features to target features and adds the valid rows in batch order
// (archive.add_batch; base features go along when the archive keeps them). `targets` is a
// scratch buffer. Returns the number of rows that entered the archive.
template <EliteArchive Archive>
Index insert_batch(Archive& archive, const FeatureMap& feature_map, const RowMatrix& genotypes,
                   const EvaluationBatch& evaluations, RowMatrix& targets) {
  const Index count = genotypes.rows();
  targets.resize(count, feature_map.output_size());
  feature_map.map(evaluations.base_features.data(), count, targets.data());
  return archive.add_batch({genotypes,
                            {evaluations.fitness.data(), static_cast<std::size_t>(evaluations.fitness.size())},
                            targets,
                            evaluations.base_features,
                            evaluations.valid});
}

class MapElites final : public Algorithm {
 public:
  // `archive` gets its solution size from the task; its qd_offset from the task too.
  MapElites(MapElitesParams params, Task task, std::unique_ptr<FeatureMap> feature_map,
            GridArchiveParams archive, MutationParams mutation, std::uint64_t seed);

  std::string name() const override { return "map-elites"; }
  std::int64_t generation() const override { return generation_; }
  EvaluationCounters counters() const override { return counters_; }
  ArchiveStats stats() const override { return archive_.stats(); }
  EliteTable elites() const override;
  const GridArchive& archive() const { return archive_; }
  bool checkpointable() const override { return true; }
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

 protected:
  // One request per step: the generation's genotypes, one job.
  void next_request(std::vector<EvaluationJob>& jobs) override;
  bool take_results() override;

 private:
  MapElitesParams params_;
  Task task_;
  std::unique_ptr<FeatureMap> feature_map_;
  GridArchive archive_;
  Mutation mutation_;
  std::uint64_t seed_;
  std::int64_t generation_ = 0;
  EvaluationCounters counters_;
  RowMatrix genotypes_;
  EvaluationBatch evaluations_;
  RowMatrix targets_;
};

// Evaluation counters in checkpoints (shared by every algorithm).
void save_counters(BinaryWriter& out, const EvaluationCounters& c);
EvaluationCounters load_counters(BinaryReader& in);

}  // namespace qdmeta
