#include "qdmeta/algorithms/aurora.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void AuroraParams::validate() const {
  require_range("aurora.batch_size", batch_size, Index{1}, Index{10'000'000});
  require_range("aurora.initial_population", initial_population, Index{1}, Index{100'000'000});
  require_range("aurora.latent_size", latent_size, Index{1}, Index{1'000});
  require_range("aurora.size_control_gain", size_control_gain, 0.0, 1.0);
  require_range("aurora.threshold_factor", threshold_factor, 1e-12, 1e12);
  require_range("aurora.rebuild_every", rebuild_every, 1, 100'000'000);
  require_range("aurora.retrain_period_step", retrain_period_step, 1, 100'000'000);
  require_range("aurora.retrain_period_max", retrain_period_max, 1, 100'000'000);
  // The autoencoder's and the archive's own checks name the remaining keys.
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
  a.descriptor_size = p.latent_size;
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
double initial_threshold(const RowMatrix& descriptors, double factor, Index target) {
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

void Aurora::train(const RowMatrix& base_features) {
  Rng rng = Rng::stream(seed_, {key(StreamKey::kAutoencoder), 0, static_cast<std::uint64_t>(generation_)});
  last_training_ = autoencoder_.train(base_features, rng);
  ++trainings_;
  trained_ = true;
}

void Aurora::refill(const RowMatrix& solutions, const std::vector<Real>& objectives, const RowMatrix& base_features,
                    bool initialise_threshold) {
  const Index count = solutions.rows();
  const Eigen::MatrixXd codes = autoencoder_.encode(base_features.data(), count);
  // z-scoring over the members (population SD; a constant code keeps scale 1).
  latent_mean_ = codes.colwise().mean();
  const Eigen::MatrixXd centred = codes.rowwise() - latent_mean_;
  latent_scale_ = (centred.colwise().squaredNorm() / static_cast<double>(count)).cwiseSqrt();
  for (Index j = 0; j < latent_scale_.size(); ++j)
    if (!(latent_scale_[j] > 1e-12)) latent_scale_[j] = 1.0;
  const RowMatrix descriptors = describe(base_features.data(), count);

  if (initialise_threshold) threshold_ = initial_threshold(descriptors, params_.threshold_factor, params_.target_size);
  else control_size();

  archive_.clear();
  const double relaxed = threshold_ * (1.0 - params_.eps);
  for (Index i = 0; i < count; ++i)
    archive_.add(solutions.row(i).data(), objectives[static_cast<std::size_t>(i)], descriptors.row(i).data(),
                 base_features.row(i).data(), relaxed);
}

void Aurora::rebuild() {
  const Index m = archive_.size();
  RowMatrix solutions(m, task_.genotype_size());
  RowMatrix base(m, task_.base_feature_size());
  std::vector<Real> objectives(static_cast<std::size_t>(m));
  for (Index i = 0; i < m; ++i) {
    std::copy_n(archive_.solution(i), solutions.cols(), solutions.row(i).data());
    std::copy_n(archive_.base_features(i), base.cols(), base.row(i).data());
    objectives[static_cast<std::size_t>(i)] = archive_.objective(i);
  }
  if (generation_ == next_retraining_) {
    train(base);
    ++scheduled_trainings_;
    next_retraining_ =
        generation_ + std::min<std::int64_t>(std::int64_t{params_.retrain_period_step} * (scheduled_trainings_ + 1),
                                             params_.retrain_period_max);
  }
  refill(solutions, objectives, base, false);
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
  const Index n = task_.genotype_size();
  counters_.bottom += genotypes_.rows();

  std::vector<Index> valid;
  for (Index r = 0; r < genotypes_.rows(); ++r)
    if (evaluations_.valid[static_cast<std::size_t>(r)]) valid.push_back(r);

  if (!trained_) {
    // The first valid rows are the first training set and the first archive content.
    if (!valid.empty()) {
      const auto count = static_cast<Index>(valid.size());
      RowMatrix solutions(count, n), base(count, task_.base_feature_size());
      std::vector<Real> objectives(valid.size());
      for (Index i = 0; i < count; ++i) {
        const Index r = valid[static_cast<std::size_t>(i)];
        solutions.row(i) = genotypes_.row(r);
        base.row(i) = evaluations_.base_features.row(r);
        objectives[static_cast<std::size_t>(i)] = evaluations_.fitness[r];
      }
      train(base);
      next_retraining_ = generation_ + 1;
      refill(solutions, objectives, base, true);
    }
  } else {
    if (generation_ == next_retraining_ || generation_ % params_.rebuild_every == 0) rebuild();
    control_size();
    if (!valid.empty()) {
      // Offspring rows are encoded as one block, then inserted in batch order.
      RowMatrix base(static_cast<Index>(valid.size()), task_.base_feature_size());
      for (std::size_t i = 0; i < valid.size(); ++i) base.row(static_cast<Index>(i)) = evaluations_.base_features.row(valid[i]);
      const RowMatrix descriptors = describe(base.data(), base.rows());
      for (std::size_t i = 0; i < valid.size(); ++i) {
        const Index r = valid[i];
        archive_.add(genotypes_.row(r).data(), evaluations_.fitness[r], descriptors.row(static_cast<Index>(i)).data(),
                     base.row(static_cast<Index>(i)).data(), threshold_);
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
  save_counters(out, counters_);
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
  counters_ = load_counters(in);
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
}

}  // namespace qdmeta
