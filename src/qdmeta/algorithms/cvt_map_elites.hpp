#pragma once
// CVT-MAP-Elites (Vassiliades et al.; docs/specification.md, CVT-MAP-Elites): MAP-Elites whose cells are the
// Voronoi cells of k-means centroids in the base-feature space. Same loop as MapElites (random
// initial population, then batches of mutated elites drawn uniformly); a solution's descriptor is
// its base features, its cell the nearest centroid. The centroids are a value the algorithm is
// given, or makes by its source at the first step, on the evaluator's workers; it reads no file
// (the centroid cache is assembly's: assembly/cvt_centroids.hpp).
#include <functional>
#include <memory>
#include <optional>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/kmeans.hpp"
#include "qdmeta/core/evaluator.hpp"
#include "qdmeta/core/memory_estimate.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta {

// How an offspring's cell is found; all give the same cell (the exact nearest centroid).
// parent-bound: from the parent's neighbour list when its bound proves the answer, else the full
// search; brute-force: always the full search (NearestCentroid::find: the blocked product over
// all centroids, or in 3 dimensions or fewer the bucket grid); auto: parent-bound above 3
// dimensions, brute-force at 3 or fewer, where the grid beats any list walk (bench/README.md).
enum class CvtSearch { kParentBound, kBruteForce, kAuto };
inline constexpr EnumNames<CvtSearch, 3> kCvtSearchNames{
    {{CvtSearch::kAuto, "auto"}, {CvtSearch::kParentBound, "parent-bound"}, {CvtSearch::kBruteForce, "brute-force"}}};
// The search `search` means for descriptors of `dimensions` (auto resolved).
CvtSearch resolve_cvt_search(CvtSearch search, Index dimensions);

// Makes the centroids (kmeans.centroids x base features) when the first step needs them, on the
// workers of `workers`, or on the calling thread when it is null (the same bits either way).
using CentroidSource = std::function<RowMatrix(Evaluator* workers)>;

struct CvtMapElitesParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp).
  static constexpr IntParam kLookupChunk{"cvt", "lookup_chunk", 1, 1'000'000,
      "offspring per parallel nearest-centroid task (speed only: results do not depend on it)"};
  static constexpr IntParam kNeighbours{"cvt", "neighbours", 1, 100'000,
      "parent-bound: centroids in each elite's neighbour list (capped at `centroids`)"};
  MapElitesParams map_elites;        // batch size and initial population
  KMeansParams kmeans;               // the centroid count, and how `make_centroids` makes them
  Index lookup_chunk = 50;           // offspring per parallel nearest-centroid task, >= 1
  CvtSearch search = CvtSearch::kAuto;  // settle offspring from the parent's neighbours, or always search
  Index neighbours = 256;            // parent-bound: neighbour list length per elite, >= 1
  // Centroids given instead of made (cvt.centroids_file; e.g. the authors' file): then
  // kmeans.centroids x base-features in [0, 1], and `make_centroids` never runs.
  std::shared_ptr<const RowMatrix> centroids;
  // Where the centroids come from otherwise (a run's: assembly/cvt_centroids.hpp, the cache or
  // k-means over the points [cvt] names); empty: k-means over kmeans.samples uniform points.
  CentroidSource make_centroids;
  void validate() const;
};

// What CVT-MAP-Elites allocates: its archive and neighbour lists, k-means's points, offspring.
void add_cvt_map_elites_memory(MemoryEstimate& m, const CvtMapElitesParams& p, const Task& task);

class CvtMapElites final : public Algorithm {
 public:
  CvtMapElites(CvtMapElitesParams params, Task task, MutationParams mutation, std::uint64_t seed);

  std::string name() const override { return "cvt-map-elites"; }
  std::int64_t generation() const override { return generation_; }
  ArchiveStats stats() const override;
  // index = centroid index, measures = descriptor (base features), solutions = genotypes.
  EliteTable elites() const override;

  // Takes the centroids from the params' source and makes the empty archive (step() calls it; a
  // first ask() without it makes them on the calling thread). The source runs on the
  // evaluator's workers.
  void prepare(Evaluator& evaluator);
  bool prepared() const { return archive_.has_value(); }
  // Centroids to use instead of making them, before the archive is made (a pickled Python
  // Algorithm brings its own: k-means at the paper's size takes minutes).
  void give_centroids(std::shared_ptr<const RowMatrix> centroids);
  const CvtArchive& archive() const;
  // Offspring whose cell needed the full search (the rest were settled by the parent bound).
  std::int64_t searched() const { return searched_; }
  bool checkpointable() const override { return true; }
  void save(BinaryWriter& out) const override;
  // Takes the centroids first (their source on the calling thread).
  void load(BinaryReader& in) override;

 protected:
  // One request per step, one job; tell() finds the cells on oneTBB, then inserts in batch order.
  void next_request(std::vector<EvaluationJob>& jobs) override;
  bool take_results() override;
  void before_step(Evaluator& evaluator) override;
  void make_archive(Evaluator* workers);
  // A step changes the state only in its one tell(): undoing it is dropping its request.
  void save_undo(BinaryWriter& out) const override { save_generation_undo(out); }
  void load_undo(BinaryReader& in) override { load_generation_undo(in); }
  bool parallel_inside() const override { return true; }

 private:
  CvtMapElitesParams params_;
  Task task_;
  Mutation mutation_;
  std::uint64_t seed_;
  CvtSearch search_;  // params_.search resolved for the task's base features
  std::optional<CvtArchive> archive_;
  std::int64_t generation_ = 0;
  std::int64_t searched_ = 0;
  RowMatrix genotypes_;
  EvaluationBatch evaluations_;
  std::vector<Index> parents_;
  std::vector<Index> cells_;
  std::vector<std::uint8_t> settled_;  // 1: the row's cell came from its parent's neighbour list
  std::vector<Index> searched_per_chunk_;
  std::vector<Index> entering_;  // rows that would enter the archive as it was before the batch
  NeighbourLists lists_;         // their neighbour lists, one row per batch row
  std::vector<std::uint8_t> remade_;  // per entering row: 1 when its list is made from all centroids
  std::vector<Index> remade_rows_;    // those rows, and their descriptors
  RowMatrix remade_points_;
};

}  // namespace qdmeta
