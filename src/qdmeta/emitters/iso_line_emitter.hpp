#pragma once
// The iso+line operator as an emitter (Vassiliades & Mouret 2018; pyribs's IsoLineEmitter): each
// row is x_i + iso_sigma N(0, I) + line_sigma N(0, 1) (x_j - x_i) for two uniformly drawn elites
// x_i, x_j (drawn with replacement), the line's normal shared by every gene of the row, clamped
// to the bounds when they are finite. While the archive is empty x_i = x_j = x0, so a row is x0
// plus the isotropic noise. It learns nothing from tell().
#include <limits>
#include <vector>

#include "qdmeta/emitters/emitter.hpp"

namespace qdmeta {

struct IsoLineEmitterParams {
  std::vector<double> x0;  // the parents while the archive is empty, one value per gene (required)
  static constexpr RealParam kIsoSigma{"emitters", "iso_sigma", 0.0, kNoUpper, Open::kNone,
                                       "iso-line only: the isotropic noise's SD on every gene (pyribs's "
                                       "IsoLineEmitter `iso_sigma`)"};
  static constexpr RealParam kLineSigma{"emitters", "line_sigma", 0.0, kNoUpper, Open::kNone,
                                        "iso-line only: the SD of the step along the line between two elites "
                                        "(pyribs's `line_sigma`)"};
  double iso_sigma = 0.01;   // SD of the isotropic noise on every gene (kIsoSigma)
  double line_sigma = 0.2;   // SD of the step along x_j - x_i (kLineSigma)
  int batch_size = 64;       // rows per ask (kEmitterBatchSize)
  double lower_bound = -std::numeric_limits<double>::infinity();  // genes are clamped to these
  double upper_bound = std::numeric_limits<double>::infinity();   // (> lower_bound)
  // Throws InputError naming the field, its value and the rule it breaks.
  void validate() const;
};

class IsoLineEmitter : public StatelessEmitter {
 public:
  IsoLineEmitter(IsoLineEmitterParams params, ElitePicker pick_elite);

  const IsoLineEmitterParams& params() const { return params_; }
  // Per row: the draw of x_i, the draw of x_j, the line's normal, then solution_size() normals
  // in gene order.
  const RowMatrix& ask(Rng& rng) override;

 private:
  IsoLineEmitterParams params_;
  ElitePicker pick_elite_;
  std::vector<double> first_, second_;
};

}  // namespace qdmeta
