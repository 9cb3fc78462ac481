#pragma once
// MAP-Elites as an emitter (pyribs's GaussianEmitter): each row is a uniformly drawn elite plus
// N(0, sigma^2) in every gene (x0 plus that noise while the archive is empty), clamped to the
// bounds when they are finite. It learns nothing from tell(). A scheduler of Gaussian emitters
// at alpha = 1 is MAP-Elites with Gaussian variation.
#include <limits>
#include <vector>

#include "qdmeta/emitters/emitter.hpp"

namespace qdmeta {

struct GaussianEmitterParams {
  std::vector<double> x0;  // the parent while the archive is empty, one value per gene (required)
  static constexpr RealParam kSigma{"emitters", "sigma", 0.0, kNoUpper, Open::kLower,
                                    "gaussian only: the noise's SD on every gene, in gene units (pyribs's "
                                    "GaussianEmitter `sigma`)"};
  double sigma = 0.1;      // SD of the noise on every gene (kSigma)
  int batch_size = 36;     // rows per ask (kEmitterBatchSize)
  double lower_bound = -std::numeric_limits<double>::infinity();  // genes are clamped to these
  double upper_bound = std::numeric_limits<double>::infinity();   // (> lower_bound)
  // Throws InputError naming the field, its value and the rule it breaks.
  void validate() const;
};

class GaussianEmitter : public StatelessEmitter {
 public:
  GaussianEmitter(GaussianEmitterParams params, ElitePicker pick_elite);

  const GaussianEmitterParams& params() const { return params_; }
  // Per row: the elite draw, then solution_size() normals in gene order.
  const RowMatrix& ask(Rng& rng) override;

 private:
  GaussianEmitterParams params_;
  ElitePicker pick_elite_;
  std::vector<double> parent_;
};

}  // namespace qdmeta
