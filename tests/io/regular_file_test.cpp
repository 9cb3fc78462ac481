// Tests of src/qdmeta/io/regular_file.{hpp,cpp} and of AtomicFile and CsvAppender on top of it:
// what stands in a run directory in place of a file (a FIFO, a device, a directory, a link) is
// refused or replaced, never read forever, read whole into memory, or written through.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/io/run_lock.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

class RegularFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("qdmeta_regular_file_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static std::string error_of(const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(RegularFileTest, ReadsARegularFileWholeAndThroughALink) {
  const std::string text(10'000, 'x');
  const fs::path p = write("a.txt", text);
  EXPECT_EQ(read_regular_file(p, 10'000), text);
  EXPECT_EQ(regular_file_size(p, 10'000), 10'000u);
  fs::create_symlink(p, dir_ / "link.txt");
  EXPECT_EQ(read_regular_file(dir_ / "link.txt", 10'000), text);
  EXPECT_EQ(read_regular_file(write("empty.txt", ""), 10), "");
}

TEST_F(RegularFileTest, AFileLargerThanItsBoundIsRefusedNamingIt) {
  const fs::path p = write("big.txt", std::string(101, 'x'));
  const std::string msg = error_of([&] { read_regular_file(p, 100); });
  EXPECT_NE(msg.find("big.txt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("101 bytes, more than the 100"), std::string::npos) << msg;
  EXPECT_NE(error_of([&] { regular_file_size(p, 100); }), "");
}

TEST_F(RegularFileTest, AFifoIsRefusedAtOnceNotWaitedOn) {
  const fs::path fifo = dir_ / "checkpoint.bin";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  const std::string msg = error_of([&] { read_regular_file(fifo, 100); });
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));  // no writer ever comes
  EXPECT_NE(msg.find("checkpoint.bin\" is a FIFO, not a regular file"), std::string::npos) << msg;
  EXPECT_NE(error_of([&] { regular_file_size(fifo, 100); }).find("a FIFO"), std::string::npos);
}

TEST_F(RegularFileTest, DevicesAndDirectoriesAreRefused) {
  fs::create_symlink("/dev/zero", dir_ / "zero");
  EXPECT_NE(error_of([&] { read_regular_file(dir_ / "zero", kMaxBinaryFileBytes); }).find("is a character device"),
            std::string::npos);
  fs::create_directory(dir_ / "sub");
  EXPECT_NE(error_of([&] { read_regular_file(dir_ / "sub", 100); }).find("is a directory"), std::string::npos);
  EXPECT_NE(error_of([&] { read_regular_file(dir_ / "none", 100); }).find("does not exist"), std::string::npos);
}

TEST_F(RegularFileTest, AProcFileIsReadToItsEndThoughItSaysZeroBytes) {
  ASSERT_EQ(fs::file_size("/proc/self/status"), 0u);
  const std::string status = read_regular_file("/proc/self/status", 1'000'000);
  EXPECT_NE(status.find("Name:"), std::string::npos);
  EXPECT_NE(error_of([&] { read_regular_file("/proc/self/status", 10); }).find("more than the 10 bytes"),
            std::string::npos);
}

TEST_F(RegularFileTest, PathTakenSeesADanglingLink) {
  fs::create_symlink(dir_ / "nowhere", dir_ / "dangling");
  EXPECT_FALSE(fs::exists(dir_ / "dangling"));
  EXPECT_TRUE(path_taken(dir_ / "dangling"));
  EXPECT_FALSE(path_taken(dir_ / "nothing"));
}

TEST_F(RegularFileTest, CreatingAFileReplacesAPlantedLinkInsteadOfWritingThroughIt) {
  const fs::path victim = write("victim.txt", "keep me");
  fs::create_symlink(victim, dir_ / "metrics.csv");
  fs::create_symlink(dir_ / "elsewhere.csv", dir_ / "meta.csv");  // dangling
  for (const char* name : {"metrics.csv", "meta.csv"}) {
    CsvAppender out(dir_ / name, {"a", "b"});
    out.row({"1", "2"});
    EXPECT_FALSE(fs::is_symlink(dir_ / name)) << name;
    EXPECT_EQ(slurp(dir_ / name), "a,b\n1,2\n") << name;
  }
  EXPECT_EQ(slurp(victim), "keep me");
  EXPECT_FALSE(fs::exists(dir_ / "elsewhere.csv"));
}

TEST_F(RegularFileTest, ContinuingALogThroughALinkIsRefused) {
  const fs::path victim = write("victim.csv", "a,b\n1,2\n");
  fs::create_symlink(victim, dir_ / "metrics.csv");
  EXPECT_THROW(CsvAppender(dir_ / "metrics.csv", {"a", "b"}, 4, fnv1a64("a,b\n")), Error);
  EXPECT_EQ(slurp(victim), "a,b\n1,2\n");
}

TEST_F(RegularFileTest, AContinuedLogMustHashToWhatTheCheckpointSaw) {
  const fs::path p = write("metrics.csv", "a,b\n1,2\n3,4\n");
  const std::uint64_t kept = fnv1a64("a,b\n1,2\n");
  CsvAppender::check_continuable(p, {"a", "b"}, 8, kept);
  write("metrics.csv", "a,b\n1,n\n3,4\n");  // a value changed since, same length
  const std::string msg = error_of([&] { CsvAppender::check_continuable(p, {"a", "b"}, 8, kept); });
  EXPECT_NE(msg.find("differ from those the checkpoint saw"), std::string::npos) << msg;
  write("metrics.csv", "a,b\n1,2\n3,4\n");
  {
    CsvAppender out(p, {"a", "b"}, 8, kept);
    EXPECT_EQ(out.hash(), kept);
    out.row({"5", "6"});
    EXPECT_EQ(out.hash(), fnv1a64("a,b\n1,2\n5,6\n"));
    EXPECT_EQ(out.bytes(), 12u);
  }
  EXPECT_EQ(slurp(p), "a,b\n1,2\n5,6\n");
}

TEST_F(RegularFileTest, AnAtomicFileNeverWritesThroughAPlantedTemporaryOrTarget) {
  const fs::path victim = write("victim.txt", "keep me");
  // What the old fixed temporary name was: a link planted there must not be written through.
  fs::create_symlink(victim, dir_ / "config.toml.tmp");
  fs::create_symlink(victim, dir_ / "config.toml");
  write_file_atomic(dir_ / "config.toml", "seed = 1\n");
  EXPECT_EQ(slurp(victim), "keep me");
  EXPECT_FALSE(fs::is_symlink(dir_ / "config.toml"));
  EXPECT_EQ(slurp(dir_ / "config.toml"), "seed = 1\n");
}

TEST_F(RegularFileTest, TwoWritersOfOneFileAtOnceBothSucceed) {
  // As two runs making one centroid cache file, or two test phases of one run, do.
  const fs::path p = dir_ / "adapt-dimension.csv";
  AtomicFile first(p), second(p);
  EXPECT_NE(first.temporary_path(), second.temporary_path());
  first.write("one");
  second.write("two");
  EXPECT_NO_THROW(first.commit());
  EXPECT_NO_THROW(second.commit());
  EXPECT_EQ(slurp(p), "two");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(RegularFileTest, ANewFileGetsTheUsualPermissions) {
  const mode_t old = ::umask(022);
  write_file_atomic(dir_ / "summary.json", "{}\n");
  ::umask(old);
  EXPECT_EQ(fs::status(dir_ / "summary.json").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read | fs::perms::others_read);
}

// --- What a killed writer leaves: its temporaries, removed by the next holder of the run lock.

TEST(Temporaries, OnlyTheNamesAWriterGivesAreTemporaries) {
  EXPECT_TRUE(is_temporary_name("archive.csv.tmp-1234-0"));
  EXPECT_TRUE(is_temporary_name("checkpoint.bin.tmp-99999-17"));
  EXPECT_FALSE(is_temporary_name("archive.csv"));
  EXPECT_FALSE(is_temporary_name("notes.tmp-mine"));
  EXPECT_FALSE(is_temporary_name("a.tmp-12-"));
  EXPECT_FALSE(is_temporary_name("a.tmp--3"));
  EXPECT_FALSE(is_temporary_name(".tmp-1-2"));
}

TEST(Temporaries, AnExclusiveRunLockRemovesThemASharedOneDoesNot) {
  const fs::path dir = fs::temp_directory_path() / ("qdmeta_temporaries_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  for (const char* name : {"archive.csv.tmp-1-2", "sub/metrics.csv.tmp-1-3", "notes.tmp-mine", "archive.csv"})
    std::ofstream(dir / name) << "x";
  { const RunLock shared(dir, RunLock::Mode::kShared); }
  EXPECT_TRUE(fs::exists(dir / "archive.csv.tmp-1-2"));  // a shared holder may sit beside a writer's
  { const RunLock exclusive(dir, RunLock::Mode::kExclusive); }
  EXPECT_FALSE(fs::exists(dir / "archive.csv.tmp-1-2"));
  EXPECT_TRUE(fs::exists(dir / "sub/metrics.csv.tmp-1-3"));  // another directory's
  EXPECT_TRUE(fs::exists(dir / "notes.tmp-mine"));
  EXPECT_TRUE(fs::exists(dir / "archive.csv"));
  fs::remove_all(dir);
}

TEST(Temporaries, ADirectoryTooLongForARunsFilesIsRefusedBeforeItIsMade) {
  fs::path dir = fs::temp_directory_path() / ("qdmeta_long_" + std::to_string(getpid()));
  const fs::path top = dir;
  while (dir.native().size() < PATH_MAX - kRunFileNameRoom) dir /= std::string(100, 'd');
  EXPECT_THROW(RunLock(dir, RunLock::Mode::kExclusive, RunLock::Missing::kCreate), InputError);
  EXPECT_FALSE(fs::exists(top));
}

TEST_F(RegularFileTest, AContinuedFileMustNotBeALink) {
  const fs::path real = write("real.csv", "a,b\n1,2\n");
  fs::create_symlink(real, dir_ / "link.csv");
  EXPECT_THROW(refuse_symbolic_link(dir_ / "link.csv"), InputError);
  EXPECT_NO_THROW(refuse_symbolic_link(real));
  EXPECT_NO_THROW(refuse_symbolic_link(dir_ / "missing.csv"));
  const std::string text = "a,b\n1,2\n";
  EXPECT_THROW(CsvAppender::check_continuable(dir_ / "link.csv", {"a", "b"}, text.size(), fnv1a64(text)), InputError);
  EXPECT_NO_THROW(CsvAppender::check_continuable(real, {"a", "b"}, text.size(), fnv1a64(text)));
}

}  // namespace
}  // namespace qdmeta
