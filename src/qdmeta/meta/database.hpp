#pragma once
// QD-Meta's database (docs/specification.md, QD-Meta): a circular buffer of <genotype, base features,
// fitness> that keeps the newest `capacity` valid bottom-level evaluations, overwriting the
// oldest. Storage is struct-of-arrays and contiguous (one row-major block for genotypes, one
// for base features, one array of fitness), so a rebuild reads the stored rows oldest-first as
// at most two contiguous segments. The base features are also kept feature-major (one row of
// capacity + kDatabasePadding floats per feature, padding zero), the layout a map rebuild's
// network kernel reads, so rebuilds need no transposition.
#include <array>
#include <cstdint>
#include <vector>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

// Columns after the last slot of the feature-major copy, zero: a kernel that reads a whole
// number of steps past a segment's end stays inside the buffer (at least kKernelRows).
inline constexpr Index kDatabasePadding = 16;

struct DatabaseParams {
  Index capacity = 500'000;     // rows kept, >= 1; the oldest row is overwritten when full
  Index genotype_size = 0;      // genes per row, >= 1 (from the task)
  Index base_feature_size = 0;  // base features per row, >= 0 (from the task)
  void validate() const;
  bool operator==(const DatabaseParams&) const = default;
};

// The stored rows as plain data, oldest first: what a checkpoint writes and reads back.
struct DatabaseState {
  DatabaseParams params;
  std::int64_t total_inserted = 0;  // rows ever inserted, overwritten ones included
  RowMatrix genotypes;              // size x genotype_size
  RowMatrix base_features;          // size x base_feature_size
  std::vector<Real> fitness;        // size
  bool operator==(const DatabaseState& other) const;
};

// A run of stored rows, contiguous in memory: rows first_rank .. first_rank + count - 1 by age
// (rank 0 = the oldest stored row).
struct DatabaseSegment {
  Index first_rank = 0;
  Index count = 0;
  const Real* genotypes = nullptr;      // count x genotype_size, row-major
  const Real* base_features = nullptr;  // count x base_feature_size, row-major
  const Real* fitness = nullptr;        // count
  const Real* base_t = nullptr;         // feature k of row i at base_t[k * base_t_ld + i]
  Index base_t_ld = 0;
  Index genotype_size = 0;
  Index base_feature_size = 0;
  const Real* genotype(Index i) const { return genotypes + i * genotype_size; }
  const Real* base_row(Index i) const { return base_features + i * base_feature_size; }
};

// The stored rows, oldest first, as at most two segments (none when the database is empty).
struct DatabaseSegments {
  std::array<DatabaseSegment, 2> items{};
  int count = 0;
  const DatabaseSegment* begin() const { return items.data(); }
  const DatabaseSegment* end() const { return items.data() + count; }
  int size() const { return count; }
};

class Database {
 public:
  // Throws InputError naming the field when `params` is invalid.
  explicit Database(DatabaseParams params);
  Database(Index capacity, Index genotype_size, Index base_feature_size);
  // Restores a state written by state(); throws InputError when its sizes disagree.
  explicit Database(const DatabaseState& state);

  const DatabaseParams& params() const { return params_; }
  Index capacity() const { return params_.capacity; }
  Index genotype_size() const { return params_.genotype_size; }
  Index base_feature_size() const { return params_.base_feature_size; }
  Index size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::int64_t total_inserted() const { return total_inserted_; }

  // Appends one row (genotype_size genes, base_feature_size base features), overwriting the
  // oldest when full. `base` may be null when base_feature_size is 0.
  void insert(const Real* genotype, const Real* base, Real fitness);
  // Appends the valid rows of a batch in batch order. Throws InputError when the batch's sizes
  // disagree with each other or with the database (naming both sizes).
  void insert_valid(const RowMatrix& genotypes, const EvaluationBatch& evaluations);
  // Forgets every row; total_inserted() is kept.
  void clear();

  // Row of age rank `rank` (0 = oldest, size() - 1 = newest). Throws Error outside [0, size).
  const Real* genotype(Index rank) const { return genotypes_.row(slot(rank)).data(); }
  const Real* base_features(Index rank) const { return base_.row(slot(rank)).data(); }
  Real fitness(Index rank) const { return fitness_[static_cast<std::size_t>(slot(rank))]; }

  DatabaseSegments segments() const;

  DatabaseState state() const;
  // Checkpoints: the rows oldest first. load() requires the same params (InputError otherwise).
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);
  // Same parameters, same total_inserted and the same rows in the same age order.
  bool operator==(const Database& other) const;

 private:
  Index slot(Index rank) const;
  Index oldest() const { return size_ < params_.capacity ? 0 : next_; }

  DatabaseParams params_;
  RowMatrix genotypes_;        // capacity x genotype_size
  RowMatrix base_;             // capacity x base_feature_size
  std::vector<Real> base_t_;   // base_feature_size x (capacity + kDatabasePadding), feature-major
  std::vector<Real> fitness_;  // capacity
  Index next_ = 0;             // slot the next insert writes
  Index size_ = 0;
  std::int64_t total_inserted_ = 0;
};

}  // namespace qdmeta
