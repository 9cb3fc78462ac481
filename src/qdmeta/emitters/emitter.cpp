#include "qdmeta/emitters/emitter.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

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
