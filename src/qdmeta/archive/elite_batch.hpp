#pragma once
// A block of candidate elites for an archive's add_batch(): row r is one candidate (solution,
// objective, measures, base features), skipped when valid[r] is 0. Views only; the caller
// keeps the data alive for the call.
#include <cstdint>
#include <span>
#include <string_view>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

// What adding a candidate did: nothing, replaced a worse elite, or filled an empty cell.
enum class AddStatus : std::uint8_t { kNotAdded = 0, kImproved = 1, kNew = 2 };

// `rows` x `cols` row-major values, `stride` apart (>= cols).
struct RowsView {
  const Real* data = nullptr;
  Index rows = 0;
  Index cols = 0;
  Index stride = 0;
  RowsView() = default;
  RowsView(const Real* d, Index r, Index c) : data(d), rows(r), cols(c), stride(c) {}
  RowsView(const Real* d, Index r, Index c, Index s) : data(d), rows(r), cols(c), stride(s) {}
  RowsView(const RowMatrix& m) : RowsView(m.data(), m.rows(), m.cols()) {}  // NOLINT: views convert implicitly
  const Real* row(Index r) const { return data + r * stride; }
  bool given() const { return data != nullptr || rows > 0; }
};

struct EliteBatch {
  RowsView solutions;                   // rows x solution size
  std::span<const Real> objectives;     // one per row
  RowsView measures;                    // rows x the archive's measure (descriptor) size
  RowsView base_features;               // rows x base-feature size; required when the archive keeps them
  std::span<const std::uint8_t> valid;  // one per row; empty: every row is valid
  Index rows() const { return solutions.rows; }
  bool is_valid(Index r) const { return valid.empty() || valid[static_cast<std::size_t>(r)] != 0; }
};

// Throws InputError, naming `archive` and what was expected, unless the batch's shapes fit an
// archive of these sizes (base features are ignored when base_feature_size is 0), every valid
// row's objective and measures are finite, and `status_size` is 0 or the row count.
void check_batch(const EliteBatch& batch, std::size_t status_size, Index solution_size, Index measure_size,
                 Index base_feature_size, std::string_view archive);

}  // namespace qdmeta
