// Tests of src/qdmeta/experiment/checkpoint.{hpp,cpp}: a checkpoint forged with a valid checksum
// is still refused when its program version is not one this program continues, or when the
// archive it restores holds values no run writes.
#include "qdmeta/run/checkpoint.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "../expect_input_error.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/run/run.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kConfig = "algorithm = \"map-elites\"\n[budget]\nevaluations = 2000\n";
constexpr std::size_t kMagicBytes = 18;

fs::path fresh_checkpoint_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("qdmeta_checkpoint_test_" + std::to_string(getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

BuiltRun build() { return build_run(toml::parse(kConfig), "test.toml", {}); }

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The checkpoint of a run after a few steps, in `dir`; returns the run's elites.
EliteTable checkpointed_run(const fs::path& dir) {
  BuiltRun run = build();
  auto evaluator = make_evaluator(1);
  for (int i = 0; i < 3; ++i) run.algorithm->step(*evaluator);
  write_checkpoint(dir, run.settings.fingerprint, RunCursor{}, *run.algorithm);
  return run.algorithm->elites();
}

// Writes `bytes` (a checkpoint without its checksum) with a checksum that matches them.
void write_with_checksum(const fs::path& dir, std::string bytes) {
  BinaryWriter checksum;
  checksum.value(fnv1a64(bytes));
  std::ofstream(dir / kCheckpointFile, std::ios::binary) << bytes + checksum.bytes();
}

std::string without_checksum(const fs::path& dir) {
  const std::string bytes = slurp(dir / kCheckpointFile);
  return bytes.substr(0, bytes.size() - sizeof(std::uint64_t));
}

// `f` throws an InputError whose message holds `part`.
void expect_input_error(auto&& f, const std::string& part) {
  const std::string message = input_error_message(f);
  EXPECT_NE(message.find(part), std::string::npos) << message;
}

void read_back(const fs::path& dir) {
  BuiltRun run = build();
  read_checkpoint(dir, run.settings.fingerprint, *run.algorithm);
}

// The checkpoint in `dir` with its program version (whatever it is) replaced by `version`, checksum recomputed.
void forge_version(const fs::path& dir, const std::string& version) {
  std::string bytes = without_checksum(dir);
  const std::size_t at = kMagicBytes + sizeof(std::uint32_t);  // the version's length, then its bytes
  std::uint64_t length = 0;
  std::memcpy(&length, bytes.data() + at, sizeof length);
  BinaryWriter forged;
  forged.string(version);
  bytes.replace(at, sizeof length + length, forged.bytes());
  write_with_checksum(dir, bytes);
}

TEST(Checkpoint, OnlyThisProgramsVersionResumes) {
  const fs::path dir = fresh_checkpoint_dir("version");
  checkpointed_run(dir);
  const std::string good = slurp(dir / kCheckpointFile);
  EXPECT_NO_THROW(read_back(dir));
  for (const std::string& version : {std::string("0.0.9"), std::string("9.9.9")}) {
    forge_version(dir, version);
    expect_input_error([&] { read_back(dir); }, "was written by qdmeta " + version + ", whose runs this qdmeta");
  }
  for (const std::string& version : {std::string(), std::string(1 << 20, '1'), std::string("0.1.0\nforged")}) {
    forge_version(dir, version);
    expect_input_error([&] { read_back(dir); }, "is damaged: its program version is not a version");
  }
  std::ofstream(dir / kCheckpointFile, std::ios::binary) << good;
  EXPECT_NO_THROW(read_back(dir));
}

// 0.2.0 and 0.3.0 changed the API (CHANGELOG.md), not what a run draws: 0.1.0 and 0.2.0
// checkpoints resume.
TEST(Checkpoint, AVersionListedAsContinuedResumes) {
  ASSERT_NE(std::string(kVersion), "0.1.0");
  ASSERT_NE(std::string(kVersion), "0.2.0");
  const fs::path dir = fresh_checkpoint_dir("listed-version");
  checkpointed_run(dir);
  forge_version(dir, "0.1.0");
  EXPECT_NO_THROW(read_back(dir));
  forge_version(dir, "0.2.0");
  EXPECT_NO_THROW(read_back(dir));
  forge_version(dir, "0.1.1");
  expect_input_error([&] { read_back(dir); }, "was written by qdmeta 0.1.1, whose runs this qdmeta");
}

// The checkpoint in `dir` with the first occurrence of `value`'s bytes replaced by `by`'s.
void forge_value(const fs::path& dir, Real value, Real by) {
  std::string bytes = without_checksum(dir);
  const std::string from(reinterpret_cast<const char*>(&value), sizeof value);
  const std::size_t at = bytes.find(from, kMagicBytes);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, sizeof by, std::string(reinterpret_cast<const char*>(&by), sizeof by));
  write_with_checksum(dir, bytes);
}

TEST(Checkpoint, ARestoredArchiveIsValueCheckedAsAdaptChecksArchiveCsv) {
  const fs::path dir = fresh_checkpoint_dir("values");
  const EliteTable elites = checkpointed_run(dir);
  ASSERT_GT(elites.size(), 0);
  const std::string good = slurp(dir / kCheckpointFile);
  forge_value(dir, elites.objective[0], std::numeric_limits<Real>::quiet_NaN());
  // Refused as the archive's cells are read back (the same check as a pickled archive's load).
  expect_input_error([&] { read_back(dir); }, "has a non-finite objective or measure: the saved state is damaged");
  std::ofstream(dir / kCheckpointFile, std::ios::binary) << good;
  forge_value(dir, elites.solutions(0, 0), Real{2});
  expect_input_error([&] { read_back(dir); }, "has a gene 2, where every gene must lie in [0, 1]");
}

}  // namespace
}  // namespace qdmeta
