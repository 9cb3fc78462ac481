#pragma once
// Plain MAP-Elites over a grid archive (docs/specification.md, MAP-Elites): an initial population of random
// genotypes, then generations of `batch_size` offspring, each a mutated copy of a parent drawn
// uniformly from the filled cells; no crossover. Target features come from a FeatureMap.
#include <algorithm>
#include <memory>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
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
// archive with sample_cell(rng) and solution(cell) (GridArchive, CvtArchive); with `parents`,
// records each row's parent cell there.
template <class Archive>
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
template <class Archive>
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
// Maps base features to target features and inserts the valid rows in batch order.
// `targets` is a scratch buffer. Returns the number of rows that entered the archive.
Index insert_batch(GridArchive& archive, const FeatureMap& feature_map, const RowMatrix& genotypes,
                   const EvaluationBatch& evaluations, RowMatrix& targets);

class MapElites final : public Algorithm {
 public:
  // `archive` gets its solution size from the task; its qd_offset from the task too.
  MapElites(MapElitesParams params, Task task, std::unique_ptr<FeatureMap> feature_map,
            GridArchiveParams archive, MutationParams mutation, std::uint64_t seed);

  std::string name() const override { return "map-elites"; }
  void step(Evaluator& evaluator) override;
  std::int64_t generation() const override { return generation_; }
  EvaluationCounters counters() const override { return counters_; }
  ArchiveStats stats() const override { return archive_.stats(); }
  EliteTable elites() const override;
  const GridArchive& archive() const { return archive_; }
  bool checkpointable() const override { return true; }
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

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

// The elites of a grid archive as a table (shared by every grid-based algorithm).
EliteTable grid_elites(const GridArchive& archive);

}  // namespace qdmeta
