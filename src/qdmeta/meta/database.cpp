#include "qdmeta/meta/database.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "qdmeta/core/huge_pages.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void DatabaseParams::validate() const {
  require_at_least("database.capacity", capacity, Index{1});
  require_at_least("database genotype size", genotype_size, Index{1});
  require_at_least("database base-feature size", base_feature_size, Index{0});
}

bool DatabaseState::operator==(const DatabaseState& other) const {
  auto same = [](const RowMatrix& a, const RowMatrix& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && std::equal(a.data(), a.data() + a.size(), b.data());
  };
  return params == other.params && total_inserted == other.total_inserted && same(genotypes, other.genotypes) &&
         same(base_features, other.base_features) && fitness == other.fitness;
}

Database::Database(DatabaseParams params) : params_(params) {
  params_.validate();
  genotypes_.resize(params_.capacity, params_.genotype_size);
  base_.resize(params_.capacity, params_.base_feature_size);
  // Rebuilds copy each cell's winner from a random row of these (tens of MB): huge pages spare
  // most of the TLB misses. resize() has not touched them yet.
  advise_huge_pages(genotypes_.data(), static_cast<std::size_t>(genotypes_.size()) * sizeof(Real));
  advise_huge_pages(base_.data(), static_cast<std::size_t>(base_.size()) * sizeof(Real));
  base_t_.assign(static_cast<std::size_t>(params_.base_feature_size * (params_.capacity + kDatabasePadding)), Real{0});
  fitness_.assign(static_cast<std::size_t>(params_.capacity), Real{0});
}

Database::Database(Index capacity, Index genotype_size, Index base_feature_size)
    : Database(DatabaseParams{capacity, genotype_size, base_feature_size}) {}

Database::Database(const DatabaseState& state) : Database(state.params) {
  const Index rows = state.genotypes.rows();
  if (rows > params_.capacity)
    throw InputError(fmt::format("database state holds {} rows but its capacity is {}", rows, params_.capacity));
  if (state.genotypes.cols() != params_.genotype_size || state.base_features.cols() != params_.base_feature_size ||
      state.base_features.rows() != rows || static_cast<Index>(state.fitness.size()) != rows)
    throw InputError(fmt::format(
        "database state sizes disagree: genotypes {}x{}, base features {}x{}, fitness {}; expected N x {}, N x {}, N",
        rows, state.genotypes.cols(), state.base_features.rows(), state.base_features.cols(), state.fitness.size(),
        params_.genotype_size, params_.base_feature_size));
  if (state.total_inserted < rows)
    throw InputError(fmt::format("database state holds {} rows but says only {} were ever inserted", rows,
                                 state.total_inserted));
  genotypes_.topRows(rows) = state.genotypes;
  base_.topRows(rows) = state.base_features;
  const Index ld = params_.capacity + kDatabasePadding;
  for (Index r = 0; r < rows; ++r)
    for (Index k = 0; k < params_.base_feature_size; ++k)
      base_t_[static_cast<std::size_t>(k * ld + r)] = state.base_features(r, k);
  std::copy(state.fitness.begin(), state.fitness.end(), fitness_.begin());
  size_ = rows;
  next_ = rows % params_.capacity;
  total_inserted_ = state.total_inserted;
}

void Database::insert(const Real* genotype, const Real* base, Real fitness) {
  std::copy_n(genotype, params_.genotype_size, genotypes_.row(next_).data());
  if (params_.base_feature_size > 0) {
    std::copy_n(base, params_.base_feature_size, base_.row(next_).data());
    const Index ld = params_.capacity + kDatabasePadding;
    for (Index k = 0; k < params_.base_feature_size; ++k) base_t_[static_cast<std::size_t>(k * ld + next_)] = base[k];
  }
  fitness_[static_cast<std::size_t>(next_)] = fitness;
  next_ = next_ + 1 == params_.capacity ? 0 : next_ + 1;
  size_ = std::min(size_ + 1, params_.capacity);
  ++total_inserted_;
}

void Database::insert_valid(const RowMatrix& genotypes, const EvaluationBatch& evaluations) {
  const Index count = genotypes.rows();
  if (genotypes.cols() != params_.genotype_size)
    throw InputError(fmt::format("database: genotypes have {} genes but the database stores {}", genotypes.cols(),
                                 params_.genotype_size));
  if (evaluations.size() != count || evaluations.base_features.rows() != count ||
      static_cast<Index>(evaluations.valid.size()) != count)
    throw InputError(fmt::format(
        "database: batch of {} genotypes but {} fitness values, {} base-feature rows and {} valid flags", count,
        evaluations.size(), evaluations.base_features.rows(), evaluations.valid.size()));
  if (evaluations.base_features.cols() != params_.base_feature_size)
    throw InputError(fmt::format("database: evaluations have {} base features but the database stores {}",
                                 evaluations.base_features.cols(), params_.base_feature_size));
  for (Index r = 0; r < count; ++r)
    if (evaluations.valid[static_cast<std::size_t>(r)])
      insert(genotypes.row(r).data(), evaluations.base_features.row(r).data(), evaluations.fitness[r]);
}

void Database::clear() {
  size_ = 0;
  next_ = 0;
}

Index Database::slot(Index rank) const {
  if (rank < 0 || rank >= size_)
    throw Error(fmt::format("database: row {} requested but {} rows are stored", rank, size_));
  const Index s = oldest() + rank;
  return s < params_.capacity ? s : s - params_.capacity;
}

DatabaseSegments Database::segments() const {
  DatabaseSegments out;
  auto segment = [&](Index first_rank, Index first_slot, Index count) {
    DatabaseSegment& s = out.items[static_cast<std::size_t>(out.count++)];
    s.first_rank = first_rank;
    s.count = count;
    s.genotypes = genotypes_.data() + first_slot * params_.genotype_size;
    s.base_features = base_.data() + first_slot * params_.base_feature_size;
    s.fitness = fitness_.data() + first_slot;
    s.base_t = base_t_.data() + first_slot;
    s.base_t_ld = params_.capacity + kDatabasePadding;
    s.genotype_size = params_.genotype_size;
    s.base_feature_size = params_.base_feature_size;
  };
  if (size_ == 0) return out;
  const Index start = oldest();
  const Index first_count = std::min(size_, params_.capacity - start);
  segment(0, start, first_count);
  if (first_count < size_) segment(first_count, 0, size_ - first_count);
  return out;
}

DatabaseState Database::state() const {
  DatabaseState s;
  s.params = params_;
  s.total_inserted = total_inserted_;
  s.genotypes.resize(size_, params_.genotype_size);
  s.base_features.resize(size_, params_.base_feature_size);
  s.fitness.resize(static_cast<std::size_t>(size_));
  for (const DatabaseSegment& seg : segments()) {
    std::copy_n(seg.genotypes, seg.count * params_.genotype_size,
                s.genotypes.data() + seg.first_rank * params_.genotype_size);
    std::copy_n(seg.base_features, seg.count * params_.base_feature_size,
                s.base_features.data() + seg.first_rank * params_.base_feature_size);
    std::copy_n(seg.fitness, seg.count, s.fitness.data() + seg.first_rank);
  }
  return s;
}

bool Database::operator==(const Database& other) const {
  if (params_ != other.params_ || size_ != other.size_ || total_inserted_ != other.total_inserted_) return false;
  for (Index rank = 0; rank < size_; ++rank) {
    if (fitness(rank) != other.fitness(rank)) return false;
    if (!std::equal(genotype(rank), genotype(rank) + params_.genotype_size, other.genotype(rank))) return false;
    if (!std::equal(base_features(rank), base_features(rank) + params_.base_feature_size, other.base_features(rank)))
      return false;
  }
  return true;
}


void Database::save(BinaryWriter& out) const {
  const DatabaseState s = state();
  out.tag("database");
  out.value<std::int64_t>(params_.capacity);
  out.value<std::int64_t>(params_.genotype_size);
  out.value<std::int64_t>(params_.base_feature_size);
  out.value<std::int64_t>(s.total_inserted);
  out.matrix(s.genotypes);
  out.matrix(s.base_features);
  out.values(s.fitness);
}

void Database::load(BinaryReader& in) {
  in.expect_tag("database");
  DatabaseState s;
  s.params.capacity = in.value<std::int64_t>("database capacity");
  s.params.genotype_size = in.value<std::int64_t>("database genotype size");
  s.params.base_feature_size = in.value<std::int64_t>("database base-feature size");
  if (s.params != params_)
    in.fail(fmt::format("database of capacity {} ({} genes, {} base features) does not fit this run's ({}, {}, {})",
                        s.params.capacity, s.params.genotype_size, s.params.base_feature_size, params_.capacity,
                        params_.genotype_size, params_.base_feature_size));
  s.total_inserted = in.value<std::int64_t>("database total inserted");
  in.matrix(s.genotypes, "database genotypes");
  in.matrix(s.base_features, "database base features");
  s.fitness = in.values<Real>("database fitness");
  try {
    *this = Database(s);
  } catch (const InputError& e) {
    in.fail(e.what());
  }
}

}  // namespace qdmeta
