#include "qdmeta/algorithms/aurora.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void AuroraParams::validate() const {
  require(kBatchSize, batch_size);
  require(kInitialPopulation, initial_population);
  require(AutoencoderParams::kLatentSize, latent_size);
  require(AutoencoderParams::kLearningRate, learning_rate);
  require(AutoencoderParams::kMaxEpochs, max_epochs);
  require(AutoencoderParams::kMaxTrainingRows, max_training_rows);
  require(UnstructuredArchiveParams::kTargetSize, target_size);
  require(UnstructuredArchiveParams::kEps, eps);
  require(UnstructuredArchiveParams::kNoveltyNeighbours, novelty_neighbours);
  require(kSizeControlGain, size_control_gain);
  require(kThresholdFactor, threshold_factor);
  require(kRebuildEvery, rebuild_every);
  require(kRetrainPeriodStep, retrain_period_step);
  require(kRetrainPeriodMax, retrain_period_max);
  // The autoencoder's own checks name aurora.hidden's entries.
}

namespace {

AutoencoderParams autoencoder_params(const AuroraParams& p, const Task& task) {
  AutoencoderParams a;
  a.input_size = task.base_feature_size();
  a.latent_size = p.latent_size;
  a.hidden = p.hidden;
  a.learning_rate = p.learning_rate;
  a.max_epochs = p.max_epochs;
  a.max_training_rows = p.max_training_rows;
  return a;
}

UnstructuredArchiveParams archive_params(const AuroraParams& p, const Task& task) {
  UnstructuredArchiveParams a;
  a.measure_size = p.latent_size;
  a.solution_size = task.genotype_size();
  a.base_feature_size = task.base_feature_size();
  a.target_size = p.target_size;
  a.eps = p.eps;
  a.novelty_neighbours = p.novelty_neighbours;
  a.qd_offset = task.qd_offset();
  return a;
}

const AuroraParams& checked(const AuroraParams& p) {
  p.validate();
  return p;
}

Autoencoder make_autoencoder(const AuroraParams& p, const Task& task, std::uint64_t seed) {
  Rng init = Rng::stream(seed, {key(StreamKey::kAutoencoder), 1});
  return Autoencoder(autoencoder_params(p, task), init);
}

// 0.5 (V / target)^(1/d), V the product of the descriptors' ranges along their principal axes
// (AURORA's volume-based initial threshold).
double initial_threshold(const Eigen::Ref<const RowMatrix>& descriptors, double factor, Index target) {
  Eigen::MatrixXd centred = descriptors.cast<double>();
  centred.rowwise() -= centred.colwise().mean();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> pca(centred.transpose() * centred);
  const Eigen::MatrixXd projected = centred * pca.eigenvectors();
  const double volume = (projected.colwise().maxCoeff() - projected.colwise().minCoeff()).prod();
  const double l = factor * std::pow(volume / static_cast<double>(target), 1.0 / static_cast<double>(descriptors.cols()));
  // A degenerate archive (all codes on a line or a point) has no volume: keep l positive.
  return l > 0.0 && std::isfinite(l) ? l : 1e-6;
}

}  // namespace

void add_aurora_memory(MemoryEstimate& m, const AuroraParams& p, const Task& task) {
  constexpr auto kFloat = static_cast<double>(sizeof(Real));
  std::vector<double> widths{static_cast<double>(task.base_feature_size())};
  for (Index h : p.hidden) widths.push_back(static_cast<double>(h));
  widths.push_back(static_cast<double>(p.latent_size));
  for (auto h = p.hidden.rbegin(); h != p.hidden.rend(); ++h) widths.push_back(static_cast<double>(*h));
  widths.push_back(static_cast<double>(task.base_feature_size()));
  double weights = 0, units = 0;
  for (std::size_t i = 0; i + 1 < widths.size(); ++i) weights += (widths[i] + 1) * widths[i + 1];
  for (double w : widths) units += w;
  const double rows = static_cast<double>(std::min(p.max_training_rows, 2 * p.target_size));
  m.add("the autoencoder's weights, gradients and Adam moments", "aurora.hidden, aurora.latent_size",
        4 * weights * sizeof(double));
  m.add("the autoencoder's activations over a training set", "aurora.max_training_rows x (aurora.hidden widths)",
        2 * rows * units * sizeof(double));
  m.add("the archive", "aurora.target_size x (genes + base features)",
        2 * static_cast<double>(p.target_size) * kFloat *
            static_cast<double>(task.genotype_size() + task.base_feature_size() + p.latent_size + 2));
  m.add("a generation's offspring", "max(aurora.initial_population, aurora.batch_size) x genes",
        offspring_bytes(static_cast<double>(std::max(p.initial_population, p.batch_size)), task));
}

Aurora::Aurora(AuroraParams params, Task task, MutationParams mutation, std::uint64_t seed)
    : params_(checked(params)),
      task_(std::move(task)),
      mutation_(mutation),
      seed_(seed),
      autoencoder_(make_autoencoder(params_, task_, seed)),
      archive_(archive_params(params_, task_)) {
  latent_mean_ = Eigen::RowVectorXd::Zero(params_.latent_size);
  latent_scale_ = Eigen::RowVectorXd::Ones(params_.latent_size);
}

RowMatrix Aurora::describe(const Real* base_features, Index count) const {
  Eigen::MatrixXd codes = autoencoder_.encode(base_features, count);
  codes.rowwise() -= latent_mean_;
  codes.array().rowwise() /= latent_scale_.array();
  return codes.cast<Real>();
}

namespace {
// A rows x cols column-major view of `buffer`, grown when too small (Eigen-allocated, so it
// starts where a Matrix of its own would: its column sums run in the same order).
Eigen::Map<Eigen::MatrixXd> grown(Eigen::VectorXd& buffer, Index rows, Index cols) {
  if (buffer.size() < rows * cols) buffer.resize(rows * cols);
  return Eigen::Map<Eigen::MatrixXd>(buffer.data(), rows, cols);
}

// Rows of Eigen's product panels (Autoencoder::encode): a row before the last whole panel of a
// call always takes the same arithmetic, the rows after it an arithmetic of their own.
constexpr Index kPanelRows = 48;
}  // namespace

void Aurora::encode_batch(const Real* base_features, Index count, Autoencoder::CodesRef out) {
  const Index inputs = task_.base_feature_size();
  // Chunks of whole row panels, the last one taking the rest: the bits of one call, on any
  // number of threads. A generation's offspring (400 rows) make two.
  const Index chunk = count < 4 * 960 ? 4 * kPanelRows : 20 * kPanelRows;
  const Index chunks = std::max<Index>(1, count / chunk);
  if (static_cast<Index>(workspaces_.size()) < chunks) workspaces_.resize(static_cast<std::size_t>(chunks));
  const auto encode_chunk = [&](Index c) {
    const Index first = c * chunk, rows = c + 1 == chunks ? count - first : chunk;
    autoencoder_.encode(base_features + first * inputs, rows, out.middleRows(first, rows),
                        workspaces_[static_cast<std::size_t>(c)]);
  };
  if (chunks == 1) {
    encode_chunk(0);
  } else {
    tbb::parallel_for(
        tbb::blocked_range<Index>(0, chunks, 1),
        [&](const tbb::blocked_range<Index>& range) {
          for (Index c = range.begin(); c < range.end(); ++c) encode_chunk(c);
        },
        tbb::simple_partitioner());
  }
}

Eigen::Map<Eigen::MatrixXd> Aurora::encode(const Real* base_features, Index count) {
  Eigen::Map<Eigen::MatrixXd> codes = grown(codes_, count, params_.latent_size);
  encode_batch(base_features, count, codes);
  return codes;
}

Eigen::Map<Eigen::MatrixXd> Aurora::encode_members(const Real* base_features, Index count) {
  const Index whole = count / kPanelRows * kPanelRows;
  if (!codes_current_ || whole < 2 * kPanelRows) return encode(base_features, count);
  const Index inputs = task_.base_feature_size(), latent = params_.latent_size;
  Eigen::Map<Eigen::MatrixXd> codes = grown(codes_, count, latent);
  // The rows from the last whole panel on, after the panel before them, as a call of their own:
  // each row the same distance from the end, so the same arithmetic as in one call over all.
  const Index tail = whole - kPanelRows;
  encode_batch(base_features + tail * inputs, count - tail, codes.middleRows(tail, count - tail));
  // Before them, the codes kept since the members were encoded (on a main path, with this
  // network), and the others gathered into whole panels (rows of zeros pad the last one).
  missing_.clear();
  for (Index i = 0; i < tail; ++i) {
    if (static_cast<std::size_t>(i) < slot_code_ok_.size() && slot_code_ok_[static_cast<std::size_t>(i)]) {
      for (Index j = 0; j < latent; ++j) codes(i, j) = slot_codes_[static_cast<std::size_t>(i * latent + j)];
    } else {
      missing_.push_back(i);
    }
  }
  if (!missing_.empty()) {
    const auto m = static_cast<Index>(missing_.size());
    const Index padded = (m + kPanelRows - 1) / kPanelRows * kPanelRows;
    gathered_.assign(static_cast<std::size_t>(padded * inputs), 0.0f);
    for (Index k = 0; k < m; ++k)
      std::copy_n(base_features + missing_[static_cast<std::size_t>(k)] * inputs, inputs, gathered_.data() + k * inputs);
    Eigen::Map<Eigen::MatrixXd> fresh = grown(gathered_codes_, padded, latent);
    encode_batch(gathered_.data(), padded, fresh);
    for (Index k = 0; k < m; ++k) codes.row(missing_[static_cast<std::size_t>(k)]) = fresh.row(k);
  }
  return codes;
}

void Aurora::keep_code(Index slot, const Eigen::Map<Eigen::MatrixXd>& codes, Index row, bool main_path) {
  const Index latent = params_.latent_size;
  const auto s = static_cast<std::size_t>(slot);
  if (slot_code_ok_.size() <= s) {
    slot_code_ok_.resize(s + 1, 0);
    slot_codes_.resize((s + 1) * static_cast<std::size_t>(latent));
  }
  for (Index j = 0; j < latent; ++j) slot_codes_[s * static_cast<std::size_t>(latent) + static_cast<std::size_t>(j)] = codes(row, j);
  slot_code_ok_[s] = main_path ? 1 : 0;
}

void Aurora::z_score(const Eigen::Map<Eigen::MatrixXd>& codes) {
  const Index count = codes.rows(), latent = codes.cols();
  descriptors_.resize(static_cast<std::size_t>(count * latent));
  for (Index i = 0; i < count; ++i)
    for (Index j = 0; j < latent; ++j)
      descriptors_[static_cast<std::size_t>(i * latent + j)] =
          static_cast<Real>((codes(i, j) - latent_mean_[j]) / latent_scale_[j]);
}

void Aurora::train(const RowMatrix& base_features) {
  Rng rng = Rng::stream(seed_, {key(StreamKey::kAutoencoder), 0, static_cast<std::uint64_t>(generation_)});
  last_training_ = autoencoder_.train(base_features, rng);
  ++trainings_;
  trained_ = true;
  codes_current_ = false;  // kept codes are the old network's
}

void Aurora::refill(Index count, const Real* solutions, const Real* objectives, const Real* base_features,
                    bool initialise_threshold) {
  const Index latent = params_.latent_size;
  const Eigen::Map<Eigen::MatrixXd> codes = encode_members(base_features, count);
  // z-scoring over the members (population SD; a constant code keeps scale 1). The centred
  // codes sit in an Eigen-allocated buffer, aligned as a Matrix of their own would be, so the
  // sums run in the same order.
  latent_mean_ = codes.colwise().mean();
  if (centred_.size() < count * latent) centred_.resize(count * latent);
  Eigen::Map<Eigen::MatrixXd> centred(centred_.data(), count, latent);
  centred = codes.rowwise() - latent_mean_;
  latent_scale_ = (centred.colwise().squaredNorm() / static_cast<double>(count)).cwiseSqrt();
  for (Index j = 0; j < latent_scale_.size(); ++j)
    if (!(latent_scale_[j] > 1e-12)) latent_scale_[j] = 1.0;
  z_score(codes);

  if (initialise_threshold)
    threshold_ = initial_threshold(Eigen::Map<const RowMatrix>(descriptors_.data(), count, latent),
                                   params_.threshold_factor, params_.target_size);
  else control_size();

  archive_.refill(count, solutions, objectives, descriptors_.data(), task_.base_feature_size() > 0 ? base_features : nullptr,
                  threshold_ * (1.0 - params_.eps), &refill_rows_);
  // Each slot keeps its member's code for the next rebuild.
  const Index whole = count / kPanelRows * kPanelRows;
  slot_code_ok_.assign(static_cast<std::size_t>(archive_.size()), 0);
  slot_codes_.resize(static_cast<std::size_t>(archive_.size() * params_.latent_size));
  for (Index s = 0; s < archive_.size(); ++s) {
    const Index row = refill_rows_[static_cast<std::size_t>(s)];
    keep_code(s, codes, row, row < whole);
  }
  codes_current_ = true;
}

void Aurora::rebuild() {
  const Index m = archive_.size(), genes = task_.genotype_size(), inputs = task_.base_feature_size();
  member_solutions_.resize(static_cast<std::size_t>(m * genes));
  member_base_.resize(static_cast<std::size_t>(m * inputs));
  member_objectives_.resize(static_cast<std::size_t>(m));
  for (Index i = 0; i < m; ++i) {
    std::copy_n(archive_.solution(i), genes, member_solutions_.data() + i * genes);
    std::copy_n(archive_.base_features(i), inputs, member_base_.data() + i * inputs);
    member_objectives_[static_cast<std::size_t>(i)] = archive_.objective(i);
  }
  if (generation_ == next_retraining_) {
    train(Eigen::Map<const RowMatrix>(member_base_.data(), m, inputs));
    ++scheduled_trainings_;
    next_retraining_ =
        generation_ + std::min<std::int64_t>(std::int64_t{params_.retrain_period_step} * (scheduled_trainings_ + 1),
                                             params_.retrain_period_max);
  }
  refill(m, member_solutions_.data(), member_objectives_.data(), member_base_.data(), false);
}

void Aurora::control_size() {
  threshold_ *= 1.0 - params_.size_control_gain * static_cast<double>(params_.target_size - archive_.size());
}

void Aurora::next_request(std::vector<EvaluationJob>& jobs) {
  const Index n = task_.genotype_size();
  // The first generation, or any that finds the archive empty (every solution so far invalid),
  // draws random genotypes; the others mutate uniformly drawn members.
  if (archive_.empty()) {
    genotypes_.resize(generation_ == 0 ? params_.initial_population : params_.batch_size, n);
    Rng rng = Rng::stream(seed_, {key(StreamKey::kInitialPopulation), static_cast<std::uint64_t>(generation_)});
    random_genotypes(genotypes_, rng);
  } else {
    genotypes_.resize(params_.batch_size, n);
    Rng rng = Rng::stream(seed_, {key(StreamKey::kVariation), static_cast<std::uint64_t>(generation_)});
    mutate_copies([&](Rng& r) { return archive_.solution(archive_.sample(r)); }, mutation_, rng, genotypes_);
  }
  evaluations_.resize(genotypes_.rows(), task_.base_feature_size());
  jobs.push_back({&task_, {genotypes_.data(), genotypes_.rows(), n}, evaluations_.view()});
}

bool Aurora::take_results() {
  const Index n = task_.genotype_size(), inputs = task_.base_feature_size();

  valid_.clear();
  for (Index r = 0; r < genotypes_.rows(); ++r)
    if (evaluations_.valid[static_cast<std::size_t>(r)]) valid_.push_back(r);
  const auto count = static_cast<Index>(valid_.size());

  if (!trained_) {
    // The first valid rows are the first training set and the first archive content.
    if (count > 0) {
      RowMatrix solutions(count, n), base(count, inputs);
      std::vector<Real> objectives(valid_.size());
      for (Index i = 0; i < count; ++i) {
        const Index r = valid_[static_cast<std::size_t>(i)];
        solutions.row(i) = genotypes_.row(r);
        base.row(i) = evaluations_.base_features.row(r);
        objectives[static_cast<std::size_t>(i)] = evaluations_.fitness[r];
      }
      train(base);
      next_retraining_ = generation_ + 1;
      refill(count, solutions.data(), objectives.data(), base.data(), true);
    }
  } else {
    if (generation_ == next_retraining_ || generation_ % params_.rebuild_every == 0) rebuild();
    control_size();
    if (count > 0) {
      // Offspring rows are encoded as one block, then inserted in batch order.
      offspring_base_.resize(static_cast<std::size_t>(count * inputs));
      for (Index i = 0; i < count; ++i)
        std::copy_n(evaluations_.base_features.row(valid_[static_cast<std::size_t>(i)]).data(), inputs,
                    offspring_base_.data() + i * inputs);
      const Eigen::Map<Eigen::MatrixXd> codes = encode(offspring_base_.data(), count);
      z_score(codes);
      const Index latent = params_.latent_size, whole = count / kPanelRows * kPanelRows;
      for (Index i = 0; i < count; ++i) {
        const Index r = valid_[static_cast<std::size_t>(i)];
        Index slot = -1;
        archive_.add(genotypes_.row(r).data(), evaluations_.fitness[r], descriptors_.data() + i * latent,
                     offspring_base_.data() + i * inputs, threshold_, &slot);
        if (slot >= 0) keep_code(slot, codes, i, i < whole);
      }
    }
  }
  ++generation_;
  return true;
}

EliteTable Aurora::elites() const {
  EliteTable t;
  const Index m = archive_.size();
  t.index.resize(static_cast<std::size_t>(m));
  t.objective.resize(static_cast<std::size_t>(m));
  t.measures.resize(m, params_.latent_size);
  t.solutions.resize(m, task_.genotype_size());
  t.base_features.resize(m, task_.base_feature_size());
  for (Index i = 0; i < m; ++i) {
    t.index[static_cast<std::size_t>(i)] = i;
    t.objective[static_cast<std::size_t>(i)] = archive_.objective(i);
    for (Index j = 0; j < params_.latent_size; ++j) t.measures(i, j) = archive_.descriptor(i, j);
    std::copy_n(archive_.solution(i), t.solutions.cols(), t.solutions.row(i).data());
    std::copy_n(archive_.base_features(i), t.base_features.cols(), t.base_features.row(i).data());
  }
  return t;
}

std::vector<std::pair<std::string, double>> Aurora::summary_extras() const {
  return {{"trainings", static_cast<double>(trainings_)},
          {"distance_threshold", threshold_},
          {"last_training_epochs", static_cast<double>(last_training_.epochs)},
          {"last_training_loss", last_training_.final_training_loss}};
}


void Aurora::save(BinaryWriter& out) const {
  require_between_steps("save()");
  out.tag("aurora");
  out.value(generation_);
  save_counters(out, counters());
  autoencoder_.save(out);
  archive_.save(out);
  out.matrix(latent_mean_);
  out.matrix(latent_scale_);
  out.value(threshold_);
  out.boolean(trained_);
  out.value(trainings_);
  out.value(scheduled_trainings_);
  out.value(next_retraining_);
  out.value<std::int64_t>(last_training_.rows);
  out.value<std::int32_t>(last_training_.epochs);
  out.boolean(last_training_.stopped_early);
  out.value(last_training_.initial_training_loss);
  out.value(last_training_.final_training_loss);
  out.value(last_training_.final_validation_loss);
}

void Aurora::load(BinaryReader& in) {
  require_between_steps("load()");
  in.expect_tag("aurora");
  generation_ = in.value<std::int64_t>("generation");
  restore_counters(load_counters(in));
  autoencoder_.load(in);
  archive_.load(in);
  in.matrix(latent_mean_, "latent mean");
  in.matrix(latent_scale_, "latent scale");
  threshold_ = in.value<double>("distance threshold");
  trained_ = in.boolean("trained flag");
  trainings_ = in.value<std::int64_t>("trainings");
  scheduled_trainings_ = in.value<std::int64_t>("scheduled trainings");
  next_retraining_ = in.value<std::int64_t>("next retraining");
  last_training_.rows = in.value<std::int64_t>("last training rows");
  last_training_.epochs = in.value<std::int32_t>("last training epochs");
  last_training_.stopped_early = in.boolean("last training stop");
  last_training_.initial_training_loss = in.value<double>("last training loss");
  last_training_.final_training_loss = in.value<double>("last training loss");
  last_training_.final_validation_loss = in.value<double>("last validation loss");
  codes_current_ = false;  // codes are not saved: the next rebuild encodes every member
}

}  // namespace qdmeta
