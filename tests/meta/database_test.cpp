#include "expect_input_error.hpp"
#include "qdmeta/meta/database.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

constexpr Index kRowGenes = 3;
constexpr Index kRowBase = 2;

// Row number i has genes (i, i + 0.25, i + 0.5), base features (-i, -i - 0.5), fitness 10 i.
struct Row {
  std::vector<Real> genes;
  std::vector<Real> base;
  Real fitness;
};
Row row_number(Index i) {
  const auto x = static_cast<Real>(i);
  return {{x, x + 0.25f, x + 0.5f}, {-x, -x - 0.5f}, 10.0f * x};
}

void insert_rows(Database& db, Index first, Index count) {
  for (Index i = first; i < first + count; ++i) {
    const Row r = row_number(i);
    db.insert(r.genes.data(), r.base.data(), r.fitness);
  }
}

// Rank `rank` of `db` holds row number `number`.
void expect_row(const Database& db, Index rank, Index number) {
  const Row r = row_number(number);
  for (Index k = 0; k < kRowGenes; ++k) {
    EXPECT_EQ(db.genotype(rank)[k], r.genes[static_cast<std::size_t>(k)]) << rank;
  }
  for (Index k = 0; k < kRowBase; ++k) {
    EXPECT_EQ(db.base_features(rank)[k], r.base[static_cast<std::size_t>(k)]) << rank;
  }
  EXPECT_EQ(db.fitness(rank), r.fitness) << rank;
}

// The segments, concatenated, are the stored rows oldest first, contiguous in memory.
void expect_segments_cover(const Database& db) {
  Index next_rank = 0;
  int count = 0;
  for (const DatabaseSegment& seg : db.segments()) {
    ++count;
    EXPECT_EQ(seg.first_rank, next_rank);
    EXPECT_GE(seg.count, 1);
    for (Index i = 0; i < seg.count; ++i) {
      const Index rank = seg.first_rank + i;
      EXPECT_EQ(seg.genotype(i), db.genotype(rank));
      EXPECT_EQ(seg.base_row(i), db.base_features(rank));
      EXPECT_EQ(seg.fitness[i], db.fitness(rank));
      EXPECT_EQ(seg.genotypes + i * kRowGenes, db.genotype(rank));  // contiguous
    }
    next_rank += seg.count;
  }
  EXPECT_EQ(next_rank, db.size());
  EXPECT_EQ(db.segments().size(), count);
  EXPECT_LE(count, 2);
}

TEST(DatabaseParams, DefaultsAndValidation) {
  const DatabaseParams defaults;
  EXPECT_EQ(defaults.capacity, 500'000);
  EXPECT_NO_THROW((DatabaseParams{500'000, 20, 20}.validate()));
  EXPECT_INPUT_ERROR(Database(0, 3, 2), "database.capacity = 0 is out of range: must be at least 1");
  EXPECT_INPUT_ERROR(Database(10, 0, 2), "database genotype size = 0 is out of range: must be at least 1");
  EXPECT_INPUT_ERROR(Database(10, 3, -1), "database base-feature size = -1 is out of range: must be at least 0");
}

TEST(Database, EmptyHasNoRowsAndNoSegments) {
  const Database db(10, kRowGenes, kRowBase);
  EXPECT_EQ(db.size(), 0);
  EXPECT_TRUE(db.empty());
  EXPECT_EQ(db.capacity(), 10);
  EXPECT_EQ(db.total_inserted(), 0);
  EXPECT_EQ(db.segments().size(), 0);
  EXPECT_THROW(db.genotype(0), Error);
}

TEST(Database, PartialFillKeepsInsertionOrder) {
  Database db(10, kRowGenes, kRowBase);
  insert_rows(db, 0, 7);
  EXPECT_EQ(db.size(), 7);
  EXPECT_EQ(db.total_inserted(), 7);
  for (Index rank = 0; rank < 7; ++rank) expect_row(db, rank, rank);
  EXPECT_EQ(db.segments().size(), 1);
  expect_segments_cover(db);
  EXPECT_THROW(db.fitness(7), Error);
  EXPECT_THROW(db.fitness(-1), Error);
}

TEST(Database, KeepsExactlyTheNewestRowsInOrder) {
  const Index n = 8;
  Database db(n, kRowGenes, kRowBase);
  insert_rows(db, 0, n * 5 / 2);  // 2.5 N
  EXPECT_EQ(db.size(), n);
  EXPECT_EQ(db.total_inserted(), n * 5 / 2);
  for (Index rank = 0; rank < n; ++rank) expect_row(db, rank, n * 5 / 2 - n + rank);
  EXPECT_EQ(db.segments().size(), 2);
  expect_segments_cover(db);
}

TEST(Database, SegmentsCoverTheStoredRowsAtEveryFill) {
  const Index n = 5;
  Database db(n, kRowGenes, kRowBase);
  for (Index inserted = 0; inserted <= 3 * n; ++inserted) {
    SCOPED_TRACE("after " + std::to_string(inserted) + " inserts");
    EXPECT_EQ(db.size(), std::min(inserted, n));
    const Index first = inserted - db.size();
    for (Index rank = 0; rank < db.size(); ++rank) expect_row(db, rank, first + rank);
    expect_segments_cover(db);
    // Full at a multiple of the capacity: one segment; otherwise two once it has wrapped.
    EXPECT_EQ(db.segments().size(), inserted == 0 ? 0 : (inserted <= n || inserted % n == 0) ? 1 : 2);
    insert_rows(db, inserted, 1);
  }
}

TEST(Database, CapacityOneKeepsTheLatestRow) {
  Database db(1, kRowGenes, kRowBase);
  for (Index i = 0; i < 4; ++i) {
    insert_rows(db, i, 1);
    EXPECT_EQ(db.size(), 1);
    expect_row(db, 0, i);
    expect_segments_cover(db);
  }
  EXPECT_EQ(db.total_inserted(), 4);
}

TEST(Database, WithoutBaseFeatures) {
  Database db(3, kRowGenes, 0);
  const Real genes[] = {1, 2, 3};
  db.insert(genes, nullptr, 5.0f);
  EXPECT_EQ(db.size(), 1);
  EXPECT_EQ(db.genotype(0)[2], 3.0f);
  EXPECT_EQ(db.fitness(0), 5.0f);
}

TEST(Database, InsertValidSkipsInvalidRowsInBatchOrder) {
  Database db(10, kRowGenes, kRowBase);
  const Index count = 6;
  RowMatrix genotypes(count, kRowGenes);
  EvaluationBatch eval;
  eval.resize(count, kRowBase);
  for (Index i = 0; i < count; ++i) {
    const Row r = row_number(i);
    for (Index k = 0; k < kRowGenes; ++k) genotypes(i, k) = r.genes[static_cast<std::size_t>(k)];
    for (Index k = 0; k < kRowBase; ++k) eval.base_features(i, k) = r.base[static_cast<std::size_t>(k)];
    eval.fitness[i] = r.fitness;
    eval.valid[static_cast<std::size_t>(i)] = (i % 3 != 1) ? 1 : 0;  // rows 1 and 4 are dead
  }
  db.insert_valid(genotypes, eval);
  ASSERT_EQ(db.size(), 4);
  EXPECT_EQ(db.total_inserted(), 4);
  const Index kept[] = {0, 2, 3, 5};
  for (Index rank = 0; rank < 4; ++rank) expect_row(db, rank, kept[rank]);
}

TEST(Database, InsertValidChecksSizes) {
  Database db(10, kRowGenes, kRowBase);
  RowMatrix genotypes(4, kRowGenes);
  genotypes.setZero();
  EvaluationBatch eval;
  eval.resize(3, kRowBase);
  EXPECT_INPUT_ERROR(db.insert_valid(genotypes, eval),
                        "database: batch of 4 genotypes but 3 fitness values, 3 base-feature rows and 3 valid flags");
  RowMatrix wide(3, kRowGenes + 1);
  EXPECT_INPUT_ERROR(db.insert_valid(wide, eval), "database: genotypes have 4 genes but the database stores 3");
  EvaluationBatch narrow;
  narrow.resize(4, kRowBase - 1);
  EXPECT_INPUT_ERROR(db.insert_valid(genotypes, narrow),
                        "database: evaluations have 1 base features but the database stores 2");
  EXPECT_EQ(db.size(), 0);
}

TEST(Database, StateRoundTripAndCopiesBehaveAlike) {
  Database db(6, kRowGenes, kRowBase);
  insert_rows(db, 0, 9);  // wrapped
  const DatabaseState state = db.state();
  EXPECT_EQ(state.genotypes.rows(), 6);
  EXPECT_EQ(state.total_inserted, 9);
  EXPECT_EQ(state.fitness.front(), row_number(3).fitness);  // oldest first
  EXPECT_EQ(state.fitness.back(), row_number(8).fitness);

  Database restored(state);
  EXPECT_TRUE(restored == db);
  EXPECT_TRUE(restored.state() == state);
  Database copy = db;
  EXPECT_TRUE(copy == db);

  // Resuming from the state equals not stopping.
  insert_rows(db, 9, 4);
  insert_rows(restored, 9, 4);
  insert_rows(copy, 9, 4);
  EXPECT_TRUE(restored == db);
  EXPECT_TRUE(copy == db);
  EXPECT_TRUE(restored.state() == db.state());
  for (Index rank = 0; rank < 6; ++rank) expect_row(restored, rank, 7 + rank);

  insert_rows(copy, 13, 1);
  EXPECT_FALSE(copy == db);
  EXPECT_FALSE(copy.state() == db.state());
}

TEST(Database, StateOfPartialFillAndBadStates) {
  Database db(10, kRowGenes, kRowBase);
  insert_rows(db, 0, 3);
  DatabaseState state = db.state();
  Database restored(state);
  EXPECT_TRUE(restored == db);
  insert_rows(db, 3, 9);
  insert_rows(restored, 3, 9);
  EXPECT_TRUE(restored == db);

  DatabaseState bad = state;
  bad.fitness.pop_back();
  EXPECT_INPUT_ERROR(Database{bad},
                        "database state sizes disagree: genotypes 3x3, base features 3x2, fitness 2; expected N x 3, "
                        "N x 2, N");
  bad = state;
  bad.params.capacity = 2;
  EXPECT_INPUT_ERROR(Database{bad}, "database state holds 3 rows but its capacity is 2");
  bad = state;
  bad.total_inserted = 1;
  EXPECT_INPUT_ERROR(Database{bad}, "database state holds 3 rows but says only 1 were ever inserted");
}

TEST(Database, ClearForgetsRowsButCountsInserts) {
  Database db(4, kRowGenes, kRowBase);
  insert_rows(db, 0, 6);
  db.clear();
  EXPECT_EQ(db.size(), 0);
  EXPECT_EQ(db.total_inserted(), 6);
  insert_rows(db, 6, 2);
  expect_row(db, 0, 6);
  expect_row(db, 1, 7);
  expect_segments_cover(db);
}

}  // namespace
}  // namespace qdmeta

namespace qdmeta {
namespace {

// The feature-major copy the rebuild reads must agree with the rows, wrapped or restored.
void expect_feature_major_copy(const Database& db) {
  for (const DatabaseSegment& seg : db.segments()) {
    ASSERT_EQ(seg.base_t_ld, db.capacity() + kDatabasePadding);
    for (Index i = 0; i < seg.count; ++i)
      for (Index k = 0; k < db.base_feature_size(); ++k)
        ASSERT_EQ(seg.base_t[k * seg.base_t_ld + i], seg.base_row(i)[k]) << "row " << seg.first_rank + i;
  }
}

TEST(Database, FeatureMajorCopyMatchesTheRows) {
  Database db(7, 2, 3);
  std::vector<Real> genes(2), base(3);
  for (int i = 0; i < 12; ++i) {
    for (int k = 0; k < 3; ++k) base[static_cast<std::size_t>(k)] = static_cast<Real>(10 * i + k);
    db.insert(genes.data(), base.data(), static_cast<Real>(i));
    expect_feature_major_copy(db);
  }
  ASSERT_EQ(db.segments().size(), 2);
  // The padding after the last slot stays zero, so a kernel step past a segment's end reads 0.
  const DatabaseSegments segments = db.segments();
  const DatabaseSegment& first = *segments.begin();
  const Real* row0 = first.base_t - (db.capacity() - first.count);  // slot 0 of feature 0
  for (Index k = 0; k < 3; ++k)
    for (Index p = 0; p < kDatabasePadding; ++p) ASSERT_EQ(row0[k * first.base_t_ld + db.capacity() + p], 0.0f);
  const Database restored(db.state());
  expect_feature_major_copy(restored);
}

}  // namespace
}  // namespace qdmeta
