#pragma once
// AURORA-CSC-Uniform (docs/specification.md, AURORA; Grillotti & Cully 2021): MAP-Elites-style evolution
// in an unstructured archive whose descriptors are the latent codes of an autoencoder trained
// on the archive's own base features, with container size control (CSC) steering the archive
// toward a target size, and uniform parent selection.
//
// One step = one generation:
//   generation 0   evaluates the initial population; the autoencoder is first trained on its
//                  base features, the distance threshold l is initialised from the latent
//                  volume (0.5 (V / target)^(1/d)), and the rows are inserted (threshold
//                  l (1 - eps)).
//   generation g   draws batch_size parents uniformly, mutates and evaluates them; retrains on
//                  the archive at the scheduled generations (1, then gaps of 20, 30, 40, ...,
//                  capped), and rebuilds the archive after each retraining and every
//                  rebuild_every generations; applies CSC, l <- l (1 - gain (target - size));
//                  then inserts the offspring in batch order.
// A rebuild re-encodes every member, z-scores the codes over the archive (those statistics then
// also serve every offspring until the next rebuild), takes one CSC step on l, empties the
// archive and re-adds every member with the threshold l (1 - eps).
#include <memory>
#include <utility>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/archive/unstructured_archive.hpp"
#include "qdmeta/core/memory_estimate.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/featuremap/autoencoder.hpp"

namespace qdmeta {

struct AuroraParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp); the autoencoder's and the archive's are AutoencoderParams' and UnstructuredArchiveParams'.
  static constexpr IntParam kBatchSize{"aurora", "batch_size", 1, 10'000'000,
      "offspring per generation (parents drawn uniformly from the archive)"};
  static constexpr IntParam kInitialPopulation{"aurora", "initial_population", 1, 100'000'000,
      "random genotypes evaluated in the first generation; they are the first training set"};
  static constexpr RealParam kSizeControlGain{"aurora", "size_control_gain", 0.0, 1.0, Open::kNone,
      "container size control: every generation l <- l (1 - gain (target - size)); 0 turns it off"};
  static constexpr RealParam kThresholdFactor{"aurora", "threshold_factor", 1e-12, 1e12, Open::kNone,
      "the initial threshold l = factor (V / target)^(1/latent_size), V the product of the latent ranges "
      "along their principal axes"};
  static constexpr IntParam kRebuildEvery{"aurora", "rebuild_every", 1, 100'000'000,
      "generations between archive rebuilds (re-encode every member, re-add all); a rebuild also follows "
      "every training"};
  static constexpr IntParam kRetrainPeriodStep{"aurora", "retrain_period_step", 1, 100'000'000,
      "retraining schedule: generation 1, then each next at last + min(step (k + 1), max), k = retrainings "
      "so far (gaps 20, 30, 40, ...)"};
  static constexpr IntParam kRetrainPeriodMax{"aurora", "retrain_period_max", 1, 100'000'000,
      "cap of the retraining gap"};
  Index batch_size = 400;               // offspring per generation, >= 1
  Index initial_population = 2000;      // random genotypes evaluated first, >= 1
  Index latent_size = 2;                // descriptor dimensions (Rastrigin 2, RHex 4), >= 1
  std::vector<Index> hidden = {32, 8};  // encoder hidden widths; the decoder mirrors them
  double learning_rate = 1e-3;          // Adam step size
  int max_epochs = 100;                 // full-batch steps per training at most
  Index max_training_rows = 10'000;     // archive rows trained on at most (uniform subsample)
  Index target_size = 10'000;           // container size control's target
  double eps = 0.1;                     // insertion rule's eps (and the rebuild's l (1 - eps))
  int novelty_neighbours = 15;          // k of the novelty score
  double size_control_gain = 5e-6;      // l <- l (1 - gain (target - size)) every generation, >= 0
  double threshold_factor = 0.5;        // l0 = factor (V / target)^(1/d), > 0
  int rebuild_every = 10;               // generations between rebuilds, >= 1
  int retrain_period_step = 10;         // gap after the k-th retraining: min(step (k + 1), max), >= 1
  int retrain_period_max = 15'000;      // cap of that gap, >= 1
  void validate() const;
};

// What AURORA allocates: the autoencoder and its training activations, the archive, offspring.
void add_aurora_memory(MemoryEstimate& m, const AuroraParams& p, const Task& task);

class Aurora final : public Algorithm {
 public:
  Aurora(AuroraParams params, Task task, MutationParams mutation, std::uint64_t seed);

  std::string name() const override { return "aurora"; }
  std::int64_t generation() const override { return generation_; }
  ArchiveStats stats() const override { return archive_.stats(); }
  // index = archive slot, measures = descriptor (z-scored latent code), base = base features.
  EliteTable elites() const override;
  std::vector<std::pair<std::string, double>> summary_extras() const override;
  bool checkpointable() const override { return true; }
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

  const UnstructuredArchive& archive() const { return archive_; }
  const Autoencoder& autoencoder() const { return autoencoder_; }
  double threshold() const { return threshold_; }
  // The latent z-scoring in force (set at every rebuild from the members' codes).
  const Eigen::RowVectorXd& latent_mean() const { return latent_mean_; }
  const Eigen::RowVectorXd& latent_scale() const { return latent_scale_; }
  std::int64_t trainings() const { return trainings_; }
  std::int64_t next_retraining() const { return next_retraining_; }
  const TrainingReport& last_training() const { return last_training_; }
  // Descriptors (z-scored latent codes, count x latent_size) of raw base-feature rows.
  RowMatrix describe(const Real* base_features, Index count) const;

 protected:
  // One request per step, one job; tell() trains, rebuilds and inserts, a rebuild's
  // independent parts spread over the evaluator's workers (the bits do not depend on them).
  void next_request(std::vector<EvaluationJob>& jobs) override;
  bool take_results() override;
  bool parallel_inside() const override { return true; }
  // A step changes the state only in its one tell(): undoing it is dropping its request.
  void save_undo(BinaryWriter& out) const override { save_generation_undo(out); }
  void load_undo(BinaryReader& in) override { load_generation_undo(in); }

 private:
  void train(const RowMatrix& base_features);
  // Latent codes of raw base-feature rows into `out` (count x latent_size), in chunks spread
  // over the evaluator's workers; the same bits as one Autoencoder::encode().
  void encode_batch(const Real* base_features, Index count, Autoencoder::CodesRef out);
  // The same into codes_ (column-major).
  Eigen::Map<Eigen::MatrixXd> encode(const Real* base_features, Index count);
  // The same for the members of a rebuild (row i = slot i), with the codes kept since they were
  // encoded where the network has not changed since and one call would give them the same bits.
  Eigen::Map<Eigen::MatrixXd> encode_members(const Real* base_features, Index count);
  // Keeps row `row` of `codes` as slot `slot`'s code; `main_path` when a call over any rows
  // gives a row those bits (it sat before the last whole panel of its call).
  void keep_code(Index slot, const Eigen::Map<Eigen::MatrixXd>& codes, Index row, bool main_path);
  // The codes z-scored with the scaling in force, as floats, row-major, into descriptors_.
  void z_score(const Eigen::Map<Eigen::MatrixXd>& codes);
  // Re-encodes the given members (row-major arrays), sets the latent z-scoring from them, sets
  // l (initialised from the latent volume, or one CSC step) and re-adds them all with the
  // threshold l (1 - eps).
  void refill(Index count, const Real* solutions, const Real* objectives, const Real* base_features,
              bool initialise_threshold);
  void rebuild();
  void control_size();

  AuroraParams params_;
  Task task_;
  Mutation mutation_;
  std::uint64_t seed_;
  Autoencoder autoencoder_;
  UnstructuredArchive archive_;
  // State a checkpoint needs besides the autoencoder (parameters, input z-scoring, Adam) and
  // the archive: all of it is here.
  Eigen::RowVectorXd latent_mean_;
  Eigen::RowVectorXd latent_scale_;
  double threshold_ = 0.0;               // l
  bool trained_ = false;
  std::int64_t trainings_ = 0;           // every training, the initial one included
  std::int64_t scheduled_trainings_ = 0; // k of the retraining schedule
  std::int64_t next_retraining_ = 1;
  std::int64_t generation_ = 0;
  TrainingReport last_training_;
  // Scratch, kept so that a generation allocates nothing once warm.
  RowMatrix genotypes_;
  EvaluationBatch evaluations_;
  std::vector<Index> valid_;
  std::vector<Real> member_solutions_, member_base_, member_objectives_;  // a rebuild's copy of the archive
  std::vector<Real> offspring_base_;                                      // the valid offspring's base features
  std::vector<Real> descriptors_;                                         // z-scored codes, row-major
  Eigen::VectorXd codes_, centred_;  // count x latent_size buffers, Eigen-allocated (aligned as a Matrix)
  std::vector<Autoencoder::Workspace> workspaces_;  // one per encoding chunk
  // Each slot's latent code (raw, before z-scoring) while the network stays the same, so that a
  // rebuild re-encodes only the members that came in since the last one: not checkpointed
  // (speed only), dropped by a training or a load.
  std::vector<double> slot_codes_;           // slot x latent_size
  std::vector<std::uint8_t> slot_code_ok_;   // by slot
  bool codes_current_ = false;
  std::vector<Index> refill_rows_, missing_;
  std::vector<Real> gathered_;
  Eigen::VectorXd gathered_codes_;
};

}  // namespace qdmeta
