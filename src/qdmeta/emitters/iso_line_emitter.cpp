#include "qdmeta/emitters/iso_line_emitter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/fused.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void IsoLineEmitterParams::validate() const {
  check_x0_and_bounds("IsoLineEmitterParams", x0, lower_bound, upper_bound);
  require(kIsoSigma, iso_sigma);
  require(kLineSigma, line_sigma);
  require(kEmitterBatchSize, batch_size);
}

namespace {
const IsoLineEmitterParams& checked(const IsoLineEmitterParams& p) {
  p.validate();
  return p;
}
}  // namespace

IsoLineEmitter::IsoLineEmitter(IsoLineEmitterParams params, ElitePicker pick_elite)
    : StatelessEmitter(checked(params).batch_size, static_cast<Index>(params.x0.size()), "IsoLineEmitter",
                       "iso-line emitter"),
      params_(std::move(params)),
      pick_elite_(std::move(pick_elite)),
      first_(params_.x0.size()),
      second_(params_.x0.size()) {}

const RowMatrix& IsoLineEmitter::ask(Rng& rng) {
  check_ask();
  for (Index r = 0; r < batch_.rows(); ++r) {
    if (pick_elite_ && pick_elite_(rng, first_)) {
      pick_elite_(rng, second_);
    } else {
      first_ = params_.x0;
      second_ = params_.x0;
    }
    const double line = params_.line_sigma * rng.normal();
    for (Index j = 0; j < batch_.cols(); ++j) {
      const auto k = static_cast<std::size_t>(j);
      // The multiply-adds written out (core/fused.hpp): the compiler's contraction does not round them.
      const double along = fused(line, second_[k] - first_[k], first_[k]);
      const double gene = fused(params_.iso_sigma, rng.normal(), along);
      batch_(r, j) = static_cast<Real>(std::clamp(gene, params_.lower_bound, params_.upper_bound));
    }
  }
  awaiting_tell_ = true;
  return batch_;
}

}  // namespace qdmeta
