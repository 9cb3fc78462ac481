#pragma once
// QD-Meta (paper Algorithm 1, docs/specification.md, QD-Meta). CMA-ES evolves feature-maps (meta-genotypes);
// each meta-generation every sampled feature-map gets a fresh grid archive rebuilt from the
// database of all solutions so far, evolves it for G MAP-Elites generations (G from the
// controller), and is scored by the meta-objective; CMA-ES and the controller then update. With
// bottom_level = kCmaMae the G generations are CMA-MAE's instead (algorithms/qd_meta_emitters.hpp).
// One step() is one meta-generation (the first also evaluates the initial population, which
// only seeds the database).
//
// Its ask/tell requests, in this order:
//   (first step only) one job: the initial population, which seeds the database;
//   then, per meta-generation, the ask() that opens it samples CMA-ES, rebuilds the lambda
//   archives from the database and asks the controller for G; then
//   for g = 0 .. G-1: lambda jobs, map i's batch_size offspring of generation g, in map order
//                     (one stream per map; inserted at tell(), the maps in parallel on oneTBB,
//                     each map then making its generation g + 1 in the same pass);
//   then one request with every map's meta-objective batches (map-major, each map's in plan
//   order), or none when the objective simulates nothing (Rastrigin's); the tell() that ends
//   the meta-generation updates the database (map by map), CMA-ES and the controller.
// So a meta-generation is G requests, plus one when the meta-objective simulates.
#include <memory>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/control/controller.hpp"
#include "qdmeta/core/meta_objective.hpp"
#include "qdmeta/core/memory_estimate.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/featuremap/neural_feature_map.hpp"
#include "qdmeta/meta/cma_es.hpp"
#include "qdmeta/meta/database.hpp"

namespace qdmeta {

// What the database stores as a solution's base features: b itself, or (the authors' Rastrigin
// code, docs/fidelity.md) 2b - 1, so that rebuilt maps read inputs in [-1,1] while fresh
// offspring are still mapped from b in [0,1].
enum class DatabaseInputs { kBaseFeatures, kAuthors2gMinus1 };
inline constexpr EnumNames<DatabaseInputs, 2> kDatabaseInputsNames{
    {{DatabaseInputs::kBaseFeatures, "base-features"}, {DatabaseInputs::kAuthors2gMinus1, "authors-2g-1"}}};

// How each map fills its archive in its G generations: the paper's MAP-Elites ([mutation] of
// uniformly drawn elites), or CMA-MAE's emitters (algorithms/qd_meta_emitters.hpp; not the paper's).
enum class BottomLevel { kMapElites, kCmaMae };
inline constexpr EnumNames<BottomLevel, 2> kBottomLevelNames{
    {{BottomLevel::kMapElites, "map-elites"}, {BottomLevel::kCmaMae, "cma-mae"}}};

struct QdMetaParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp).
  static constexpr IntParam kMetaPopulation{"qd_meta", "meta_population", 1, 10'000,
      "lambda: feature-maps sampled by CMA-ES per meta-generation (1: a (1,1)-ES, the supplementary study's "
      "smallest)"};
  static constexpr IntParam kBatchSize{"qd_meta", "batch_size", 1, 10'000'000,
      "offspring per MAP-Elites generation in each map (refused with `bottom_level = \"cma-mae\"`, whose generation "
      "is `emitters.count` x `emitters.batch_size` rows)"};
  static constexpr IntParam kInitialPopulation{"qd_meta", "initial_population", 1, 100'000'000,
      "random genotypes that only seed the database"};
  static constexpr IntParam kDatabaseCapacity{"qd_meta", "database_capacity", 1, 1'000'000'000,
      "newest solutions kept in the circular database"};
  static constexpr IntParam kHidden{"qd_meta", "hidden", 1, 10'000,
      "N_h, hidden units of each feature-map (K = N_h N_b + 1 + N_t N_h + 1 weights)"};
  static constexpr RealParam kSigmoidScale{"qd_meta", "sigmoid_scale", 0.0, kNoUpper, Open::kLower,
      "alpha_s of the scaled sigmoid S_N(x) = 1/(1+exp(-alpha_s x/(N+1)))"};
  static constexpr RealParam kCmaSigma{"cma_es", "sigma", 0.0, kNoUpper, Open::kLower,
      "initial step size (range / 3 for meta-genotypes in [-1,1])"};
  Index meta_population = 10;          // lambda, feature-maps per meta-generation (1 is a (1,1)-ES)
  Index batch_size = 400;              // offspring per MAP-Elites generation
  Index initial_population = 2000;     // random genotypes that seed the database
  Index database_capacity = 500'000;   // newest solutions kept
  Index hidden = 10;                   // N_h, hidden units of each feature-map
  double sigmoid_scale = 30.0;         // alpha_s of the scaled sigmoid
  double cma_sigma = 2.0 / 3.0;        // CMA-ES initial step size
  CmaBoundsHandling cma_bounds = CmaBoundsHandling::kClamp;
  bool frozen = false;                 // ablation: sample from the initial distribution forever
  // meta_population = 1: a (1,1)-ES, or the authors' library's realisation (docs/fidelity.md)
  CmaSmallPopulation cma_small_population = CmaSmallPopulation::kOneOne;
  DatabaseInputs database_inputs = DatabaseInputs::kBaseFeatures;
  bool count_meta_evaluations = false; // does the controller's "evaluations spent" include them
  BottomLevel bottom_level = BottomLevel::kMapElites;
  // kCmaMae: every map's emitters and thresholds; batch_size must be emitters x emitter.batch_size
  // (a generation is one ask of every emitter), and emitter.x0 serves only an empty archive.
  CmaMaeParams emitters;
  void validate() const;
};

// What QD-Meta allocates: the meta-population's archives (each `grid`), the database, every
// map's offspring of one meta-generation of up to `max_generations`, CMA-ES, the initial population.
void add_qd_meta_memory(MemoryEstimate& m, const QdMetaParams& p, const GridArchiveParams& grid, const Task& task,
                        int max_generations);

class QdMeta final : public Algorithm {
 public:
  // The archive params give the grid (one target feature per entry of bins); the solution and
  // base-feature sizes and the QD-score offset come from the task.
  QdMeta(QdMetaParams params, Task task, std::unique_ptr<MetaObjective> meta_objective, GridArchiveParams archive,
         MutationParams mutation, std::unique_ptr<GenerationController> controller, std::uint64_t seed);

  std::string name() const override { return "qd-meta"; }
  std::int64_t generation() const override { return meta_generation_; }
  // Statistics and elites of the map with the best meta-fitness of the latest meta-generation.
  ArchiveStats stats() const override { return best_archive_.stats(); }
  EliteTable elites() const override;
  const MetaGenerationRecord* last_meta_record() const override { return meta_generation_ > 0 ? &record_ : nullptr; }
  bool checkpointable() const override { return true; }
  void save(BinaryWriter& out) const override;
  // Checkpoints only between steps (save() and load() mid-step throw Error).
  void load(BinaryReader& in) override;

  const Database& database() const { return database_; }
  const CmaEs& cma_es() const { return cma_; }
  const GridArchive& best_archive() const { return best_archive_; }
  // Every map's archive at the end of the last meta-generation (not restored by load(): a
  // checkpoint keeps only the best).
  const std::vector<GridArchive>& map_archives() const { return archives_; }
  double best_meta_fitness() const { return record_.meta_fitness_best; }
  const std::vector<double>& meta_fitness() const { return meta_fitness_; }
  // Map i's feature-map of the last meta-generation (null before the first).
  const NeuralFeatureMap* feature_map(Index i) const { return maps_[static_cast<std::size_t>(i)].get(); }
  // bottom_level = kCmaMae: map i's scheduler of the last meta-generation (null before the first).
  const Scheduler<GridArchive>* emitters(Index i) const {
    return schedulers_.empty() ? nullptr : schedulers_[static_cast<std::size_t>(i)].get();
  }

 protected:
  void next_request(std::vector<EvaluationJob>& jobs) override;
  bool take_results() override;
  bool parallel_inside() const override { return true; }
  // Before its last tell() (finish_meta_generation), a step changes the counters, CMA-ES (ask)
  // and the controller (its choice), and on the first step the empty database (the seeds); the
  // rest waits for the end. Those are saved, the database only while empty.
  void save_undo(BinaryWriter& out) const override;
  void load_undo(BinaryReader& in) override;

 private:
  // Where the meta-generation stands between requests.
  enum class Phase { kIdle, kSeeding, kGenerations, kMetaScoring };
  void begin_meta_generation();
  void vary_map(Index map, int generation);
  void plan_map(Index map);
  bool meta_objective_simulates() const;
  void score_meta_fitness();
  void finish_meta_generation();
  // Inserts the valid rows into the database, their base features as params_.database_inputs says.
  void store(const RowMatrix& genotypes, const EvaluationBatch& evaluations);

  QdMetaParams params_;
  Task task_;
  std::unique_ptr<MetaObjective> meta_objective_;
  Mutation mutation_;
  std::unique_ptr<GenerationController> controller_;
  std::uint64_t seed_;
  NeuralFeatureMapShape shape_;
  CmaEs cma_;
  Database database_;
  std::vector<GridArchive> archives_;              // one per feature-map of the meta-generation
  std::vector<std::unique_ptr<NeuralFeatureMap>> maps_;
  std::vector<std::unique_ptr<Scheduler<GridArchive>>> schedulers_;  // kCmaMae: per map, made afresh each meta-generation
  std::vector<RowMatrix> offspring_;               // per map: all its new genotypes this meta-generation
  std::vector<EvaluationBatch> evaluations_;       // per map: their evaluations
  std::vector<RowMatrix> blocks_;                  // per map: the current generation's genotypes
  std::vector<EvaluationBatch> block_evaluations_; // per map: their evaluations (the request's outputs)
  std::vector<RowMatrix> targets_;                 // per map: insertion scratch
  std::vector<Task> meta_tasks_;                   // the meta-objective's tasks(), which its batches index
  struct Elites {                                  // a map's archive as its meta-objective reads it
    RowMatrix genotypes;
    Vector fitness;
    RowMatrix measures;
    RowMatrix base_features;
    MetaArchive view() const { return {genotypes, fitness, measures, base_features}; }
  };
  std::vector<Elites> elites_;                     // per map, filled cells in cell order
  std::vector<MetaPlan> plans_;                    // per map: its meta-objective plan (empty archive: none)
  std::vector<std::uint8_t> planned_;              // per map: 1 when plans_ holds a plan to score
  std::vector<std::vector<EvaluationBatch>> meta_evaluations_;  // per map: its plan's batches' results
  std::vector<MetaFitnessResult> meta_results_;
  std::vector<double> meta_fitness_;
  GridArchive best_archive_;
  MetaGenerationRecord record_;
  std::int64_t meta_generation_ = 0;
  // The meta-generation in progress (none between steps).
  Phase phase_ = Phase::kIdle;
  int generations_ = 0;        // G of this meta-generation
  int next_generation_ = 0;    // g of the next generation request
  RowMatrix seed_genotypes_;
  EvaluationBatch seed_evaluations_;
};

}  // namespace qdmeta
