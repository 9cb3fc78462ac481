#include "qdmeta/emitters/gaussian_emitter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/fused.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void GaussianEmitterParams::validate() const {
  check_x0_and_bounds("GaussianEmitterParams", x0, lower_bound, upper_bound);
  require(kSigma, sigma);
  require(kEmitterBatchSize, batch_size);
}

namespace {
const GaussianEmitterParams& checked(const GaussianEmitterParams& p) {
  p.validate();
  return p;
}
}  // namespace

GaussianEmitter::GaussianEmitter(GaussianEmitterParams params, ElitePicker pick_elite)
    : StatelessEmitter(checked(params).batch_size, static_cast<Index>(params.x0.size()), "GaussianEmitter",
                       "gaussian emitter"),
      params_(std::move(params)),
      pick_elite_(std::move(pick_elite)),
      parent_(params_.x0.size()) {}

const RowMatrix& GaussianEmitter::ask(Rng& rng) {
  check_ask();
  for (Index r = 0; r < batch_.rows(); ++r) {
    if (!(pick_elite_ && pick_elite_(rng, parent_))) parent_ = params_.x0;
    for (Index j = 0; j < batch_.cols(); ++j) {
      const double gene = fused(params_.sigma, rng.normal(), parent_[static_cast<std::size_t>(j)]);
      batch_(r, j) = static_cast<Real>(std::clamp(gene, params_.lower_bound, params_.upper_bound));
    }
  }
  awaiting_tell_ = true;
  return batch_;
}

}  // namespace qdmeta
