#include "qdmeta/featuremap/autoencoder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void AutoencoderParams::validate() const {
  require_range("aurora input size", input_size, Index{1}, Index{1'000'000});
  require(kLatentSize, latent_size);
  if (hidden.empty()) throw InputError("aurora.hidden is empty: give at least one hidden layer width");
  if (std::cmp_greater(hidden.size(), kHiddenLayers.hi))
    throw InputError(fmt::format("aurora.hidden has {} entries: must have between {} and {}", hidden.size(),
                                 kHiddenLayers.lo, kHiddenLayers.hi));
  for (Index h : hidden) require_range("aurora.hidden entry", h, Index{kHiddenWidth.lo}, Index{kHiddenWidth.hi});
  require(kLearningRate, learning_rate);
  require(kMaxEpochs, max_epochs);
  require(kMaxTrainingRows, max_training_rows);
  require_range("aurora validation fraction", validation_fraction, 1e-6, 1.0 - 1e-6);
  require_at_least("aurora split minimum rows", split_min_rows, Index{1});
  require_range("aurora stopping window", stopping_window, 2, 1'000'000);
  require_range("aurora input SD epsilon", input_sd_epsilon, 0.0, 1e6);
}

Autoencoder::Autoencoder(AutoencoderParams params, Rng& init_rng) : params_(std::move(params)) {
  params_.validate();
  // Widths: input, hidden..., latent, reversed hidden..., input.
  std::vector<Index> widths{params_.input_size};
  widths.insert(widths.end(), params_.hidden.begin(), params_.hidden.end());
  widths.push_back(params_.latent_size);
  widths.insert(widths.end(), params_.hidden.rbegin(), params_.hidden.rend());
  widths.push_back(params_.input_size);
  encoder_layers_ = params_.hidden.size() + 1;
  Index offset = 0;
  for (std::size_t l = 0; l + 1 < widths.size(); ++l) {
    // ReLU after every layer but the latent one and the output one.
    const bool relu = l + 1 != encoder_layers_ && l + 2 != widths.size();
    layers_.push_back({widths[l], widths[l + 1], offset, relu});
    offset += widths[l] * widths[l + 1] + widths[l + 1];
  }
  parameters_.resize(offset);
  for (const Layer& layer : layers_) {
    const double bound = 1.0 / std::sqrt(static_cast<double>(layer.in));
    for (Index k = 0; k < layer.in * layer.out + layer.out; ++k)
      parameters_[layer.offset + k] = init_rng.uniform(-bound, bound);
  }
  input_mean_ = Eigen::RowVectorXd::Zero(params_.input_size);
  input_scale_ = Eigen::RowVectorXd::Ones(params_.input_size);
  adam_m_ = Eigen::VectorXd::Zero(offset);
  adam_v_ = Eigen::VectorXd::Zero(offset);
}

void Autoencoder::set_parameters(const Eigen::VectorXd& parameters) {
  if (parameters.size() != parameters_.size())
    throw Error(fmt::format("autoencoder: {} parameters given, {} expected", parameters.size(), parameters_.size()));
  parameters_ = parameters;
}

const Autoencoder::Matrix& Autoencoder::forward(const Matrix& x, std::size_t layers, Scratch& scratch) const {
  std::vector<Matrix>& a = scratch.activations;
  if (a.size() < layers + 1) a.resize(layers + 1);
  for (std::size_t l = 0; l < layers; ++l) {
    const Layer& L = layers_[l];
    const Eigen::Map<const Matrix> w(parameters_.data() + L.offset, L.out, L.in);
    const Eigen::Map<const Eigen::RowVectorXd> b(parameters_.data() + L.offset + L.in * L.out, L.out);
    Matrix& out = a[l + 1];
    out.noalias() = (l == 0 ? x : a[l]) * w.transpose();
    out.rowwise() += b;
    if (L.relu) out = out.cwiseMax(0.0);
  }
  return layers == 0 ? x : a[layers];
}

Autoencoder::Matrix Autoencoder::normalise(const Real* inputs, Index count) const {
  const Eigen::Map<const RowMatrix> raw(inputs, count, params_.input_size);
  Matrix x = raw.cast<double>();
  x.rowwise() -= input_mean_;
  x.array().rowwise() /= input_scale_.array();
  return x;
}

Autoencoder::Matrix Autoencoder::encode(const Real* inputs, Index count) const {
  Matrix codes(count, params_.latent_size);
  Workspace workspace;
  encode(inputs, count, codes, workspace);
  return codes;
}

Eigen::Map<Autoencoder::Matrix> Autoencoder::Workspace::view(std::size_t index, Index rows, Index cols) {
  if (buffers_.size() <= index) buffers_.resize(index + 1);
  Eigen::VectorXd& b = buffers_[index];
  if (b.size() < rows * cols) b.resize(rows * cols);
  return Eigen::Map<Matrix>(b.data(), rows, cols);
}

namespace {
// One layer of forward() on views: out = act(in W^T + b), in the same operations.
template <class In, class Out>
void apply_layer(const In& in, const Eigen::Map<const Autoencoder::Matrix>& w,
                 const Eigen::Map<const Eigen::RowVectorXd>& b, bool relu, Out& out) {
  out.noalias() = in * w.transpose();
  out.rowwise() += b;
  if (relu) out = out.cwiseMax(0.0);
}
}  // namespace

void Autoencoder::encode(const Real* inputs, Index count, CodesRef codes, Workspace& workspace) const {
  Eigen::Map<Matrix> x = workspace.view(0, count, params_.input_size);
  x = Eigen::Map<const RowMatrix>(inputs, count, params_.input_size).cast<double>();
  x.rowwise() -= input_mean_;
  x.array().rowwise() /= input_scale_.array();
  const double* in = x.data();  // each layer's input: count x L.in, in buffers 0, 1, 2, 1, 2, ...
  for (std::size_t l = 0; l < encoder_layers_; ++l) {
    const Layer& L = layers_[l];
    const Eigen::Map<const Matrix> input(in, count, L.in);
    const Eigen::Map<const Matrix> w(parameters_.data() + L.offset, L.out, L.in);
    const Eigen::Map<const Eigen::RowVectorXd> b(parameters_.data() + L.offset + L.in * L.out, L.out);
    if (l + 1 == encoder_layers_) {
      apply_layer(input, w, b, L.relu, codes);
    } else {
      Eigen::Map<Matrix> out = workspace.view(1 + l % 2, count, L.out);
      apply_layer(input, w, b, L.relu, out);
      in = out.data();
    }
  }
}

Autoencoder::Matrix Autoencoder::reconstruct(const Matrix& x) const {
  Scratch scratch;
  return forward(x, layers_.size(), scratch);
}

double Autoencoder::loss(const Matrix& x) const {
  Scratch scratch;
  return loss(x, scratch);
}

double Autoencoder::loss(const Matrix& x, Scratch& scratch) const {
  if (x.size() == 0) return 0.0;
  return (forward(x, layers_.size(), scratch) - x).squaredNorm() / static_cast<double>(x.size());
}

double Autoencoder::loss_and_gradient(const Matrix& x, Eigen::VectorXd& gradient) const {
  Scratch scratch;
  return loss_and_gradient(x, gradient, scratch);
}

double Autoencoder::loss_and_gradient(const Matrix& x, Eigen::VectorXd& gradient, Scratch& scratch) const {
  gradient.setZero(parameters_.size());
  if (x.size() == 0) return 0.0;
  forward(x, layers_.size(), scratch);
  const std::vector<Matrix>& a = scratch.activations;
  std::vector<Matrix>& deltas = scratch.deltas;
  if (deltas.size() < layers_.size() + 1) deltas.resize(layers_.size() + 1);
  Matrix* delta = &deltas[layers_.size()];
  *delta = a[layers_.size()] - x;
  const double loss = delta->squaredNorm() / static_cast<double>(x.size());
  *delta *= 2.0 / static_cast<double>(x.size());  // d loss / d output
  for (std::size_t l = layers_.size(); l-- > 0;) {
    const Layer& L = layers_[l];
    // ReLU passes the gradient where its output was positive.
    if (L.relu) *delta = (a[l + 1].array() > 0.0).select(*delta, 0.0);
    Eigen::Map<Matrix> dw(gradient.data() + L.offset, L.out, L.in);
    Eigen::Map<Eigen::RowVectorXd> db(gradient.data() + L.offset + L.in * L.out, L.out);
    dw.noalias() = delta->transpose() * (l == 0 ? x : a[l]);
    db = delta->colwise().sum();
    if (l > 0) {
      const Eigen::Map<const Matrix> w(parameters_.data() + L.offset, L.out, L.in);
      deltas[l].noalias() = *delta * w;
      delta = &deltas[l];
    }
  }
  return loss;
}

// PyTorch's Adam defaults besides the learning rate: beta1 0.9, beta2 0.999, eps 1e-8.
void Autoencoder::adam_step(const Eigen::VectorXd& gradient) {
  constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEps = 1e-8;
  ++adam_t_;
  adam_m_ = kBeta1 * adam_m_ + (1.0 - kBeta1) * gradient;
  adam_v_ = kBeta2 * adam_v_ + (1.0 - kBeta2) * gradient.cwiseProduct(gradient);
  const double c1 = 1.0 - std::pow(kBeta1, static_cast<double>(adam_t_));
  const double c2 = 1.0 - std::pow(kBeta2, static_cast<double>(adam_t_));
  parameters_.array() -=
      params_.learning_rate * (adam_m_.array() / c1) / ((adam_v_.array() / c2).sqrt() + kEps);
}

TrainingReport Autoencoder::train(const RowMatrix& inputs, Rng& rng) {
  if (inputs.cols() != params_.input_size)
    throw Error(fmt::format("autoencoder: training rows have {} columns, {} expected", inputs.cols(),
                            params_.input_size));
  if (inputs.rows() < 1) throw Error("autoencoder: no training rows");
  TrainingReport report;

  std::vector<Index> chosen(static_cast<std::size_t>(inputs.rows()));
  std::iota(chosen.begin(), chosen.end(), Index{0});
  if (inputs.rows() > params_.max_training_rows)
    choose_without_replacement(chosen, static_cast<std::size_t>(params_.max_training_rows), rng);
  const auto n = static_cast<Index>(chosen.size());
  report.rows = n;
  Matrix raw(n, params_.input_size);
  for (Index i = 0; i < n; ++i) raw.row(i) = inputs.row(chosen[static_cast<std::size_t>(i)]).cast<double>();

  // z-scoring over the training set: population SD plus epsilon (docs/specification.md, AURORA).
  input_mean_ = raw.colwise().mean();
  Matrix x = raw.rowwise() - input_mean_;
  input_scale_ = (x.colwise().squaredNorm() / static_cast<double>(n)).cwiseSqrt().array() + params_.input_sd_epsilon;
  x.array().rowwise() /= input_scale_.array();

  adam_m_.setZero();
  adam_v_.setZero();
  adam_t_ = 0;

  const bool split = n > params_.split_min_rows;
  const Index validation_rows =
      split ? std::clamp<Index>(std::llround(params_.validation_fraction * static_cast<double>(n)), 1, n - 1) : 0;
  const Index training_rows = n - validation_rows;
  std::vector<Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Index{0});
  // Buffers of the same shapes at every training (the matrices are reassigned, so they keep
  // their memory unless the row count changes).
  Matrix& train_x = training_.train_x;
  Matrix& validation_x = training_.validation_x;
  Eigen::VectorXd gradient;
  Scratch& fit_scratch = training_.fit;
  Scratch& validation_scratch = training_.validation;
  std::vector<double> validation_losses;
  const auto window = static_cast<std::size_t>(params_.stopping_window);
  for (int epoch = 0; epoch < params_.max_epochs; ++epoch) {
    if (split) {
      std::iota(order.begin(), order.end(), Index{0});
      choose_without_replacement(order, order.size(), rng);  // a full shuffle
      train_x.resize(training_rows, params_.input_size);
      validation_x.resize(validation_rows, params_.input_size);
      for (Index i = 0; i < training_rows; ++i) train_x.row(i) = x.row(order[static_cast<std::size_t>(i)]);
      for (Index i = 0; i < validation_rows; ++i)
        validation_x.row(i) = x.row(order[static_cast<std::size_t>(training_rows + i)]);
    }
    const Matrix& fit_on = split ? train_x : x;
    const double training_loss = loss_and_gradient(fit_on, gradient, fit_scratch);
    adam_step(gradient);
    const double validation_loss = loss(split ? validation_x : x, split ? validation_scratch : fit_scratch);
    if (epoch == 0) report.initial_training_loss = training_loss;
    report.final_training_loss = training_loss;
    report.final_validation_loss = validation_loss;
    report.epochs = epoch + 1;
    validation_losses.push_back(validation_loss);
    if (validation_losses.size() >= window) {
      // Mean change over the window relative to its oldest loss, as the authors' code computes
      // it: positive when the recent losses sit above the oldest on average.
      const double oldest = validation_losses[validation_losses.size() - window];
      double mean_change = 0.0;
      for (std::size_t i = validation_losses.size() - window; i < validation_losses.size(); ++i)
        mean_change += (validation_losses[i] - oldest) / static_cast<double>(window);
      if (mean_change > 0.0 && training_loss < report.initial_training_loss) {
        report.stopped_early = true;
        break;
      }
    }
  }
  return report;
}


void Autoencoder::save(BinaryWriter& out) const {
  out.tag("autoencoder");
  out.matrix(parameters_);
  out.matrix(input_mean_);
  out.matrix(input_scale_);
}

void Autoencoder::load(BinaryReader& in) {
  in.expect_tag("autoencoder");
  Eigen::VectorXd parameters;
  Eigen::RowVectorXd mean, scale;
  in.matrix(parameters, "autoencoder weights");
  in.matrix(mean, "autoencoder input mean");
  in.matrix(scale, "autoencoder input scale");
  if (parameters.size() != parameters_.size() || mean.size() != input_mean_.size() || scale.size() != input_scale_.size())
    in.fail(fmt::format("autoencoder of {} weights does not fit this run's {}", parameters.size(), parameters_.size()));
  parameters_ = parameters;
  input_mean_ = mean;
  input_scale_ = scale;
}

}  // namespace qdmeta
