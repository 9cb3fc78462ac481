#include "qdmeta/emitters/emitter.hpp"

#include <fmt/format.h>

#include <cmath>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

void check_x0_and_bounds(std::string_view params, const std::vector<double>& x0, double lower_bound,
                         double upper_bound) {
  if (x0.empty()) throw InputError(fmt::format("{}.x0 is empty: give the first parent, one value per gene", params));
  for (std::size_t j = 0; j < x0.size(); ++j) {
    if (!std::isfinite(x0[j])) throw InputError(fmt::format("{}.x0[{}] = {} is invalid: must be finite", params, j, x0[j]));
  }
  if (std::isnan(lower_bound) || std::isnan(upper_bound) || !(upper_bound > lower_bound)) {
    throw InputError(fmt::format("{}.upper_bound = {} is invalid: must be > lower_bound = {}", params, upper_bound,
                                 lower_bound));
  }
}

void BatchEmitter::check_ask() const {
  if (awaiting_tell_) {
    throw InputError(fmt::format("{}::ask: called twice without tell; tell the last batch's outcomes first", name_));
  }
}

void BatchEmitter::check_tell(const EmitterResults& results) const {
  if (!awaiting_tell_) throw InputError(fmt::format("{}::tell: called without a pending ask; call ask() first", name_));
  const auto rows = static_cast<std::size_t>(batch_size());
  if (results.rows() != batch_size() || results.objectives.size() != rows || results.outcomes.size() != rows) {
    throw InputError(fmt::format("{}::tell: expected {} rows, objectives and outcomes; got {}, {}, {}", name_, rows,
                                 results.rows(), results.objectives.size(), results.outcomes.size()));
  }
}

void StatelessEmitter::tell(const EmitterResults& results) {
  check_tell(results);
  awaiting_tell_ = false;
}

void StatelessEmitter::save(BinaryWriter& out) const {
  out.tag(tag_);
  save_batch(out);
}

void StatelessEmitter::load(BinaryReader& in) {
  in.expect_tag(tag_);
  load_batch(in);
}

void BatchEmitter::save_batch(BinaryWriter& out) const {
  out.matrix(batch_);
  out.boolean(awaiting_tell_);
}

void BatchEmitter::load_batch(BinaryReader& in) {
  RowMatrix batch;
  in.matrix(batch, "emitter batch");
  if (batch.rows() != batch_.rows() || batch.cols() != batch_.cols()) {
    in.fail(fmt::format("the emitter batch is {}x{}, expected {}x{}", batch.rows(), batch.cols(), batch_.rows(),
                        batch_.cols()));
  }
  batch_ = std::move(batch);
  awaiting_tell_ = in.boolean("emitter pending flag");
}

}  // namespace qdmeta
