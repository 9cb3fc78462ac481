// Tests of src/qdmeta/io/csv.{hpp,cpp} and atomic_file.{hpp,cpp}: bit-exact float round trips
// through archive.csv, its header, errors naming file and line, CsvAppender, and files that are
// either whole or absent.
#include "qdmeta/io/csv.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/io/atomic_file.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

class CsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("qdmeta_csv_test_") + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& content) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  std::string read_error(const fs::path& p, EliteValues rules = EliteValues::kFinite) {
    try {
      read_elites_csv(p, rules);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no InputError)";
  }
  fs::path dir_;
};

bool same_bits(Real a, Real b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

// Floats that a naive "%g" or "%.6f" printer would not round-trip.
std::vector<Real> awkward_floats() {
  using L = std::numeric_limits<Real>;
  return {0.1f,           1.0f / 3.0f,      2.0f / 3.0f,        1e-30f,           -1e-30f,
          L::denorm_min(), -L::denorm_min(), L::min() / 3.0f,    L::min(),         -0.0f,
          0.0f,           L::max(),         L::lowest(),        L::epsilon(),     1.0f + L::epsilon(),
          16777217.0f,    123456.789f,      -2000.0f,           -578.49427f,      std::nextafter(1.0f, 0.0f),
          3.4e38f,        1e7f,             9.999999e-5f,       0.30000001f,      -0.0001234567f};
}

EliteTable make_table(Index rows, Index nm, Index ns, Index nb, Rng& rng) {
  const std::vector<Real> awkward = awkward_floats();
  std::size_t next = 0;
  auto value = [&]() -> Real {
    // Alternate awkward values with random ones (random exponent and mantissa).
    if (next < awkward.size() * 3 && (next++ % 2 == 0)) return awkward[(next / 2) % awkward.size()];
    return static_cast<Real>(std::ldexp(rng.uniform(-1.0, 1.0), static_cast<int>(rng.below(80)) - 40));
  };
  EliteTable t;
  for (Index i = 0; i < rows; ++i) {
    t.index.push_back(i == 1 ? std::int64_t{9'000'000'000} : static_cast<std::int64_t>(rng.below(10000)));
    t.objective.push_back(value());
  }
  t.measures.resize(rows, nm);
  t.solutions.resize(rows, ns);
  t.base_features.resize(rows, nb);
  for (Index k = 0; k < t.measures.size(); ++k) t.measures.data()[k] = value();
  for (Index k = 0; k < t.solutions.size(); ++k) t.solutions.data()[k] = value();
  for (Index k = 0; k < t.base_features.size(); ++k) t.base_features.data()[k] = value();
  return t;
}

void expect_same(const EliteTable& a, const EliteTable& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.index, b.index);
  ASSERT_EQ(a.measures.cols(), b.measures.cols());
  ASSERT_EQ(a.solutions.cols(), b.solutions.cols());
  ASSERT_EQ(a.base_features.cols(), b.base_features.cols());
  for (Index i = 0; i < a.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_TRUE(same_bits(a.objective[k], b.objective[k])) << a.objective[k] << " vs " << b.objective[k];
    for (Index j = 0; j < a.measures.cols(); ++j)
      EXPECT_TRUE(same_bits(a.measures(i, j), b.measures(i, j))) << a.measures(i, j) << " vs " << b.measures(i, j);
    for (Index j = 0; j < a.solutions.cols(); ++j)
      EXPECT_TRUE(same_bits(a.solutions(i, j), b.solutions(i, j))) << a.solutions(i, j) << " vs " << b.solutions(i, j);
    for (Index j = 0; j < a.base_features.cols(); ++j)
      EXPECT_TRUE(same_bits(a.base_features(i, j), b.base_features(i, j)))
          << a.base_features(i, j) << " vs " << b.base_features(i, j);
  }
}

TEST_F(CsvTest, EveryAwkwardFloatRoundTripsBitExactly) {
  // One column per awkward value, in every section of the table.
  const std::vector<Real> awkward = awkward_floats();
  const auto n = static_cast<Index>(awkward.size());
  EliteTable t;
  t.measures.resize(n, 1);
  t.solutions.resize(n, n);
  t.base_features.resize(n, 1);
  for (Index i = 0; i < n; ++i) {
    t.index.push_back(i);
    t.objective.push_back(awkward[static_cast<std::size_t>(i)]);
    t.measures(i, 0) = awkward[static_cast<std::size_t>((i + 1) % n)];
    t.base_features(i, 0) = awkward[static_cast<std::size_t>((i + 2) % n)];
    for (Index j = 0; j < n; ++j) t.solutions(i, j) = awkward[static_cast<std::size_t>((i + j) % n)];
  }
  const fs::path p = dir_ / "archive.csv";
  write_elites_csv(p, t);
  const EliteTable back = read_elites_csv(p);
  expect_same(t, back);
  // -0.0 keeps its sign.
  EXPECT_TRUE(std::signbit(back.objective[9]));
  EXPECT_EQ(back.objective[9], 0.0f);
}

TEST_F(CsvTest, RandomTableRoundTrips) {
  Rng rng(61);
  const EliteTable t = make_table(200, 2, 20, 20, rng);
  const fs::path p = dir_ / "archive.csv";
  write_elites_csv(p, t);
  expect_same(t, read_elites_csv(p));
  EXPECT_FALSE(fs::exists(dir_ / "archive.csv.tmp"));
}

TEST_F(CsvTest, HeaderColumns) {
  Rng rng(62);
  const fs::path p = dir_ / "archive.csv";
  write_elites_csv(p, make_table(3, 2, 3, 2, rng));
  std::ifstream in(p);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "index,objective,measures_0,measures_1,solution_0,solution_1,solution_2,base_0,base_1");
  int lines = 0;
  for (std::string line; std::getline(in, line);) {
    ++lines;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 8) << line;
  }
  EXPECT_EQ(lines, 3);

  // Without base features there are no base_ columns.
  write_elites_csv(p, make_table(1, 1, 2, 0, rng));
  std::ifstream in2(p);
  std::getline(in2, header);
  EXPECT_EQ(header, "index,objective,measures_0,solution_0,solution_1");
  const EliteTable back = read_elites_csv(p);
  EXPECT_EQ(back.base_features.cols(), 0);
  EXPECT_EQ(back.solutions.cols(), 2);
  EXPECT_EQ(back.measures.cols(), 1);
}

TEST_F(CsvTest, RowsAreWrittenInOrderWithIndex) {
  EliteTable t;
  t.index = {5, 17};
  t.objective = {1.5f, -2.0f};
  t.measures.resize(2, 1);
  t.measures << 0.25f, 0.75f;
  t.solutions.resize(2, 2);
  t.solutions << 0.5f, 1.0f, 0.0f, 0.125f;
  t.base_features.resize(2, 0);
  const fs::path p = dir_ / "small.csv";
  write_elites_csv(p, t);
  EXPECT_EQ(slurp(p), "index,objective,measures_0,solution_0,solution_1\n5,1.5,0.25,0.5,1\n17,-2,0.75,0,0.125\n");
}

TEST_F(CsvTest, EmptyTableRoundTrips) {
  EliteTable t;
  t.measures.resize(0, 2);
  t.solutions.resize(0, 3);
  t.base_features.resize(0, 0);
  const fs::path p = dir_ / "empty.csv";
  write_elites_csv(p, t);
  const EliteTable back = read_elites_csv(p);
  EXPECT_EQ(back.size(), 0);
  EXPECT_EQ(back.measures.cols(), 2);
  EXPECT_EQ(back.solutions.cols(), 3);
}

TEST_F(CsvTest, ReadErrorsNameFileAndLine) {
  const fs::path missing = dir_ / "missing.csv";
  std::string msg = read_error(missing);
  EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing.csv"), std::string::npos) << msg;

  msg = read_error(write("empty.csv", ""));
  EXPECT_NE(msg.find("empty.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find("is empty"), std::string::npos) << msg;

  msg = read_error(write("header.csv", "id,fitness\n1,2\n"));
  EXPECT_NE(msg.find("header.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not an archive file"), std::string::npos) << msg;

  msg = read_error(write("columns.csv", "index,objective,measures_0,solution_0\n0,1,0.5,0.5\n1,2,0.5\n"));
  EXPECT_NE(msg.find("columns.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find(":3: 3 columns, the header has 4"), std::string::npos) << msg;

  msg = read_error(write("number.csv", "index,objective,measures_0,solution_0\n0,1,0.5,0.5\n1,2,0.5,0.5\n2,abc,0.5,0.5\n"));
  EXPECT_NE(msg.find("number.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find(":4: column 2 (objective): 'abc' is not a number"), std::string::npos) << msg;

  msg = read_error(write("trailing.csv", "index,objective,measures_0,solution_0\n0,1.5x,0.5,0.5\n"));
  EXPECT_NE(msg.find(":2: column 2 (objective): '1.5x' is not a number"), std::string::npos) << msg;

  msg = read_error(write("index.csv", "index,objective,measures_0,solution_0\n0.5,1,0.5,0.5\n"));
  EXPECT_NE(msg.find(":2: column 1 (index): '0.5' is not a number"), std::string::npos) << msg;  // the index is an integer

  msg = read_error(write("blank_cell.csv", "index,objective,measures_0,solution_0\n0,1,0.5,\n"));
  EXPECT_NE(msg.find(":2: column 4 (solution_0): '' is not a number"), std::string::npos) << msg;
}

// What the writer never writes, refused as the report refuses it (tools/run_files.py): a last
// line without its end (a file cut short, its last cell 0.1 of 0.125), an empty line, a column
// name twice.
TEST_F(CsvTest, ReadRefusesALastLineCutShortAnEmptyLineAndARepeatedName) {
  std::string msg = read_error(write("cut.csv", "index,objective,measures_0,solution_0\n0,1,0.5,0.125\n1,2,0.5,0.1"));
  EXPECT_NE(msg.find("cut.csv\":3: the last line has no line end: the file was cut short"), std::string::npos) << msg;
  msg = read_error(write("blank.csv", "index,objective,measures_0,solution_0\n0,1,0.5,0.5\n\n1,2,0.5,0.5\n"));
  EXPECT_NE(msg.find("blank.csv\":3: an empty line: the file is damaged"), std::string::npos) << msg;
  msg = read_error(write("twice.csv", "index,objective,measures_0,measures_0\n0,1,0.5,0.5\n"));
  EXPECT_NE(msg.find("twice.csv\":1: column 4 'measures_0' repeats an earlier column's name"), std::string::npos)
      << msg;
  EXPECT_EQ(read_elites_csv(write("crlf.csv", "index,objective,measures_0\r\n0,1,0.5\r\n")).size(), 1);
}

TEST_F(CsvTest, ARunsArchiveHoldsEachCellOnce) {
  const fs::path twice = write("twice.csv", "index,objective,measures_0,solution_0\n0,1,0.5,0.5\n3,2,0.5,0.5\n"
                                            "3,2,0.5,0.5\n");
  const std::string msg = read_error(twice, EliteValues::kRunArchive);
  EXPECT_NE(msg.find(":4: column 1 (index): cell 3 repeats line 3: a run's archive holds one elite per cell"),
            std::string::npos)
      << msg;
  EXPECT_EQ(read_elites_csv(twice).size(), 3);  // a table of any other origin may repeat a cell
}

TEST_F(CsvTest, AppenderWritesRowsAndChecksWidth) {
  const fs::path p = dir_ / "metrics.csv";
  {
    CsvAppender out(p, {"evals", "qd_score"});
    out.row({"400", "1.5"});
    EXPECT_EQ(slurp(p), "evals,qd_score\n400,1.5\n");  // each row flushed whole
    try {
      out.row({"800"});
      FAIL() << "no exception";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("metrics.csv"), std::string::npos) << msg;
      EXPECT_NE(msg.find("row of 1 cells, the header has 2"), std::string::npos) << msg;
    }
    out.row({"800", "2"});
  }
  EXPECT_EQ(slurp(p), "evals,qd_score\n400,1.5\n800,2\n");
  EXPECT_THROW(CsvAppender(dir_ / "no_such_dir" / "x.csv", {"a"}), Error);
}

TEST_F(CsvTest, AtomicFileUncommittedLeavesNothing) {
  const fs::path p = dir_ / "out.txt";
  {
    AtomicFile f(p);
    f.write("partial");
    EXPECT_TRUE(fs::exists(f.temporary_path()));
    EXPECT_EQ(f.temporary_path().parent_path(), dir_);
    EXPECT_FALSE(fs::exists(p));
  }
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(CsvTest, AtomicFileUncommittedKeepsTheOldFile) {
  const fs::path p = write("out.txt", "old content");
  {
    AtomicFile f(p);
    f.write("new");
  }
  EXPECT_EQ(slurp(p), "old content");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(CsvTest, AtomicFileCommitReplacesAndLeavesNoTmp) {
  const fs::path p = write("out.txt", "old content that is longer");
  {
    AtomicFile f(p);
    f.write("new");
    EXPECT_EQ(slurp(p), "old content that is longer");  // untouched until commit
    f.commit();
    EXPECT_EQ(slurp(p), "new");
  }
  EXPECT_EQ(slurp(p), "new");
  write_file_atomic(p, "via helper\n");
  EXPECT_EQ(slurp(p), "via helper\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);  // no temporary left
}

TEST_F(CsvTest, AtomicFileErrors) {
  EXPECT_THROW(AtomicFile(dir_ / "no_such_dir" / "x.txt"), Error);
  EXPECT_THROW(write_elites_csv(dir_ / "no_such_dir" / "a.csv", EliteTable{}), Error);
  EXPECT_TRUE(fs::is_empty(dir_));
}

// A run's stored base features lie in [-1, 1]: QD-Meta with qd_meta.database_inputs =
// "authors-2g-1" stores 2g - 1 (genes stay in [0, 1]).
TEST_F(CsvTest, ARunsArchiveTakesStoredBaseFeaturesInMinusOneToOne) {
  const std::string header = "index,objective,measures_0,solution_0,base_0\n";
  const EliteTable t = read_elites_csv(write("signed.csv", header + "0,1,0.5,0.5,-0.5\n1,1,0.5,0.5,-1\n"),
                                       EliteValues::kRunArchive);
  EXPECT_EQ(t.base_features(0, 0), Real(-0.5));
  std::string msg = read_error(write("below.csv", header + "0,1,0.5,0.5,-1.5\n"), EliteValues::kRunArchive);
  EXPECT_NE(msg.find(":2: column 5 (base_0): -1.5 is outside [-1, 1], where every stored base feature must lie"),
            std::string::npos)
      << msg;
  msg = read_error(write("gene.csv", header + "0,1,0.5,-0.5,0.5\n"), EliteValues::kRunArchive);
  EXPECT_NE(msg.find(":2: column 4 (solution_0): -0.5 is outside [0, 1], where every gene must lie"),
            std::string::npos)
      << msg;
}

}  // namespace
}  // namespace qdmeta
