#pragma once
// AURORA's learned feature-map (docs/specification.md, AURORA): an MLP autoencoder
//   input -> 32 -> 8 -> latent -> 8 -> 32 -> input
// with ReLU after every hidden layer and linear latent and output layers, trained by Adam on
// the mean squared reconstruction error of z-scored inputs. Written with Eigen: no Debian
// package offers a small MLP trainer.
//
// Arithmetic is in double. The network is tiny (about 2,000 weights), so a retraining on 10,000
// rows costs well under a second either way, and double keeps the gradient check against finite
// differences tight and the training free of float round-off drift. Everything is serial and
// deterministic given the Rng passed in.
#include <vector>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/eigen.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct AutoencoderParams {
  // AURORA's config parameters that the autoencoder checks (core/params.hpp).
  static constexpr IntParam kLatentSize{"aurora", "latent_size", 1, 1'000,
      "descriptor dimensions (paper: 2 for Rastrigin, 4 for RHex)"};
  static constexpr RealParam kLearningRate{"aurora", "learning_rate", 1e-12, 1e3, Open::kNone,
      "Adam step size (Adam's moments are reset at every training)"};
  static constexpr IntParam kMaxEpochs{"aurora", "max_epochs", 1, 100'000'000,
      "full-batch Adam steps per training at most (early stopping may end it sooner)"};
  static constexpr IntParam kMaxTrainingRows{"aurora", "max_training_rows", 1, 100'000'000,
      "archive rows trained on at most; a larger archive is subsampled uniformly"};
  // aurora.hidden, an array: the range of each width and of the number of layers. The array is
  // read with both (ConfigReader::integers) and validate() checks both.
  static constexpr IntParam kHiddenWidth{"aurora", "hidden", 1, 100'000, "each encoder hidden width"};
  static constexpr IntParam kHiddenLayers{"aurora", "hidden", 1, 16, "encoder hidden layers"};
  Index input_size = 20;                // inputs per row (N_b), >= 1
  Index latent_size = 2;                // code size, >= 1
  std::vector<Index> hidden = {32, 8};  // encoder hidden widths, the decoder mirrors them (kHiddenWidth, kHiddenLayers)
  double learning_rate = 1e-3;          // Adam step size, > 0
  int max_epochs = 100;                 // full-batch Adam steps per training at most, >= 1
  Index max_training_rows = 10'000;     // larger training sets are subsampled uniformly, >= 1
  double validation_fraction = 0.25;    // share held out for validation, in (0, 1)
  Index split_min_rows = 500;           // the validation split is used only above this many rows
  int stopping_window = 5;              // early stopping reads the last this many validation losses, >= 2
  double input_sd_epsilon = 1e-3;       // added to each input's SD before z-scoring, >= 0
  void validate() const;
};

struct TrainingReport {
  Index rows = 0;                      // rows trained on (after subsampling)
  int epochs = 0;                      // Adam steps taken
  bool stopped_early = false;
  double initial_training_loss = 0.0;  // before the first step
  double final_training_loss = 0.0;    // before the last step
  double final_validation_loss = 0.0;  // after the last step
};

class Autoencoder {
 public:
  // One sample per row, column-major: the layout Eigen's products like best.
  using Matrix = Eigen::MatrixXd;

  // Weights and biases drawn as PyTorch's nn.Linear does: U(-1/sqrt(fan_in), 1/sqrt(fan_in)).
  Autoencoder(AutoencoderParams params, Rng& init_rng);

  const AutoencoderParams& params() const { return params_; }
  Index parameter_count() const { return parameters_.size(); }
  // All weights and biases, layer by layer: W (out x in, column-major), then b.
  const Eigen::VectorXd& parameters() const { return parameters_; }
  void set_parameters(const Eigen::VectorXd& parameters);
  // Checkpoints: the weights and the input z-scoring (Adam's moments restart with every
  // training, so they are not saved). load() requires the same network shape.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

  // The z-scoring in force (set by train(); identity before the first training).
  const Eigen::RowVectorXd& input_mean() const { return input_mean_; }
  const Eigen::RowVectorXd& input_scale() const { return input_scale_; }

  // Sets the input z-scoring from `inputs` (subsampled to max_training_rows with `rng`), resets
  // Adam, and trains: one full-batch step per epoch; above split_min_rows rows a fresh random
  // validation_fraction is held out each epoch. Stops after max_epochs, or early once the mean
  // change of the last stopping_window validation losses (each minus the oldest of them) is
  // positive while the training loss is below its initial value. Without a split the
  // validation loss is the loss on all rows.
  TrainingReport train(const RowMatrix& inputs, Rng& rng);

  // Raw rows (count x input_size, row-major) -> z-scored inputs.
  Matrix normalise(const Real* inputs, Index count) const;
  // Raw rows -> latent codes (count x latent_size).
  Matrix encode(const Real* inputs, Index count) const;

  // Scratch of the encode() below: Eigen-allocated buffers (so aligned as a Matrix is) that
  // only grow, so a warm workspace makes encoding allocate nothing. One per concurrent call.
  class Workspace {
   public:
    // A rows x cols view of buffer `index`, grown when too small.
    Eigen::Map<Matrix> view(std::size_t index, Index rows, Index cols);

   private:
    std::vector<Eigen::VectorXd> buffers_;
  };
  // encode() into `codes` (count x latent_size; a block of rows of a larger matrix will do):
  // the same bits. Eigen's product computes a row the same way wherever it sits, except the
  // rows after the last multiple of its row panel (at most 48), so a block that starts at a
  // multiple of 48 rows and, unless it is the last, ends at one, gives the rows of one whole call
  // (tests/featuremap/autoencoder_test.cpp checks it).
  using CodesRef = Eigen::Ref<Matrix, 0, Eigen::OuterStride<>>;
  void encode(const Real* inputs, Index count, CodesRef codes, Workspace& workspace) const;
  // z-scored inputs -> reconstructions (still z-scored).
  Matrix reconstruct(const Matrix& x) const;
  // Mean over all entries of (reconstruction - x)^2, for z-scored inputs x.
  double loss(const Matrix& x) const;
  // The same, with its gradient with respect to parameters() by backpropagation.
  double loss_and_gradient(const Matrix& x, Eigen::VectorXd& gradient) const;

  // Adam's moments and step count (reset by every train()); kept for checkpoints.
  const Eigen::VectorXd& adam_m() const { return adam_m_; }
  const Eigen::VectorXd& adam_v() const { return adam_v_; }

 private:
  struct Layer {
    Index in = 0;
    Index out = 0;
    Index offset = 0;  // of W in parameters_; b follows W
    bool relu = false;
  };
  // Buffers of one batch shape, kept across a training's epochs so that they are not
  // allocated again (Eigen-allocated, so aligned and summed as fresh matrices are).
  struct Scratch {
    std::vector<Matrix> activations;  // [l]: the output of layer l - 1 ([0] unused: the input)
    std::vector<Matrix> deltas;       // [l]: d loss / d (layer l's output)
  };
  // Activations of the first `layers` layers for a batch; the last one's is returned.
  const Matrix& forward(const Matrix& x, std::size_t layers, Scratch& scratch) const;
  double loss(const Matrix& x, Scratch& scratch) const;
  double loss_and_gradient(const Matrix& x, Eigen::VectorXd& gradient, Scratch& scratch) const;
  void adam_step(const Eigen::VectorXd& gradient);

  AutoencoderParams params_;
  std::vector<Layer> layers_;
  std::size_t encoder_layers_ = 0;
  Eigen::VectorXd parameters_;
  Eigen::RowVectorXd input_mean_;
  Eigen::RowVectorXd input_scale_;
  Eigen::VectorXd adam_m_;
  Eigen::VectorXd adam_v_;
  std::int64_t adam_t_ = 0;
  // train()'s buffers, kept from one training to the next (not state: never saved).
  struct TrainingBuffers {
    Matrix train_x, validation_x;
    Scratch fit, validation;
  };
  TrainingBuffers training_;
};

}  // namespace qdmeta
