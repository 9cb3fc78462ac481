// The command line under hostile or unlucky conditions: paths that a shell would interpret, two
// writers on one run directory, kills at awkward moments, damaged checkpoints and archives,
// configs that cannot fit in memory. Each test here failed before its fix.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "robustness_helpers.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

using namespace robustness;  // NOLINT(google-build-using-namespace): the shared helpers of these tests
using cli_test::slurp;

using cli_test::expect_same_run;

using cli_test::signalled_at_checkpoint;
using cli_test::while_stopped_at_checkpoint;

// --- 1. The report is started with an argument vector, never through a shell.

TEST(Robustness, NoPathIsEverInterpretedByAShell) {
  const fs::path root = fresh_dir("hostile");
  const fs::path cwd = root / "cwd";
  fs::create_directories(cwd);
  const fs::path experiment =
      write_file("tiny-experiment.toml", "name = \"tiny\"\nreplicates = 1\ntests = []\n[[condition]]\nname = \"MAP-Elites\"\n"
                                         "config = \"" + std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml\"\n");
  const std::vector<std::string> names = {"x'; touch PWNED; echo '", "with space", "dollar $(touch PWNED)",
                                          "semi;touch PWNED", "back`touch PWNED`tick", "new\nline touch PWNED"};
  for (const std::string& name : names) {
    const fs::path out = root / name;
    const Outcome o = shell("cd " + quote(cwd.string()) + " && " + kBinary + " experiment --config " +
                            quote(experiment.string()) + " --out " + quote(out.string()) + " --evals 20000 --quiet");
    EXPECT_EQ(o.status, 0) << name << "\n" << o.output;
    EXPECT_TRUE(fs::exists(out / "report.md")) << name << "\n" << o.output;
    for (const fs::path& where : {cwd, root, out})
      EXPECT_FALSE(fs::exists(where / "PWNED")) << "a shell ran part of the path '" << name << "'";
  }
}

TEST(Robustness, AFailedReportIsANonZeroExit) {
  const fs::path dir = fresh_dir("failing-report");
  fs::create_directories(dir);
  std::ofstream(dir / "experiment.toml") << "name = \"x\"\n";
  const Outcome failed = shell("QDMETA_PYTHON=/bin/false " + kBinary + " report " + quote(dir.string()));
  EXPECT_EQ(failed.status, 2) << failed.output;
  EXPECT_NE(failed.output.find("failed (exit status 1)"), std::string::npos) << failed.output;
  const Outcome missing = shell("QDMETA_PYTHON=/no/such/python " + kBinary + " report " + quote(dir.string()));
  EXPECT_EQ(missing.status, 2) << missing.output;
  EXPECT_NE(missing.output.find("cannot start /no/such/python"), std::string::npos) << missing.output;
}

// The report's own error (a damaged input) is the one line the user sees; a crash of the script
// is shown whole, then the CLI's line.
TEST(Robustness, TheReportsOwnErrorIsTheOnlyLine) {
  const fs::path dir = fresh_dir("report-error");
  fs::create_directories(dir);
  std::ofstream(dir / "experiment.toml") << "name = \"x\"\nreplicates = 1\n[[condition]]\nname = 3\n";
  const Outcome damaged = qdmeta_cli("report " + quote(dir.string()));
  EXPECT_EQ(damaged.status, 2) << damaged.output;
  EXPECT_EQ(damaged.output, "qdmeta: error: " + (dir / "experiment.toml").string() +
                                ": [[condition]] 1: name must be a non-empty string\n");
  const fs::path tools = fresh_dir("crashing-tools");
  fs::create_directories(tools);
  std::ofstream(tools / "report.py") << "raise RuntimeError('a bug in the report')\n";
  const Outcome crashed =
      shell("QDMETA_TOOLS_DIR=" + quote(tools.string()) + " " + kBinary + " report " + quote(dir.string()));
  EXPECT_EQ(crashed.status, 2) << crashed.output;
  EXPECT_NE(crashed.output.find("Traceback (most recent call last)"), std::string::npos) << crashed.output;
  EXPECT_NE(crashed.output.find("RuntimeError: a bug in the report\nqdmeta: error: the report script"),
            std::string::npos)
      << crashed.output;
}

// --- 2. One writer per run directory.

TEST(Robustness, ASecondWriterOnARunDirectoryIsRefused) {
  const fs::path dir = fresh_dir("locked");
  const fs::path log = scratch() / "locked-log";
  fs::remove_all(log);
  fs::create_directories(log);
  const std::string d = quote(dir.string());
  const auto into = [&](const std::string& name) {
    return " > " + quote((log / name).string()) + " 2>&1; echo $? > " + quote((log / (name + ".status")).string());
  };
  // A run long enough to be still writing when the others try.
  const std::string first = kBinary + " run --config " + map_elites_config() + " --out " + d +
                            " --evals 100000000000 --seed 1 --quiet --threads 1";
  const std::string during = "timeout 60 " + kBinary + " run --config " + map_elites_config() + " --out " + d +
                             " --evals 20000 --seed 2 --overwrite" + into("run") + "; timeout 60 " + kBinary + " resume --out " +
                             d + into("resume") + "; " + kBinary + " adapt --run " + d + " --test dimension" +
                             into("adapt");
  while_stopped_at_checkpoint(first, 1, during, "INT");
  for (const char* who : {"run", "resume", "adapt"}) {
    const std::string output = slurp(log / who);
    EXPECT_EQ(slurp(log / (std::string(who) + ".status")), "2\n") << who << ": " << output;
    EXPECT_NE(output.find("is in use by another qdmeta process"), std::string::npos) << who << ": " << output;
    EXPECT_EQ(count_lines(output), 1) << who << ": " << output;
  }
  EXPECT_NE(slurp(dir / "config.toml").find("seed = 1"), std::string::npos) << "the refused run changed the config";
  // The lock goes with its process: the directory is free again.
  const Outcome after = qdmeta_cli("run --config " + map_elites_config() + " --out " + d + " --evals 20000 --overwrite --quiet");
  EXPECT_EQ(after.status, 0) << after.output;
}

TEST(Robustness, AnExperimentLocksItsDirectoryAndEachRun) {
  const fs::path out = fresh_dir("locked-experiment");
  const fs::path experiment = write_file(
      "long-experiment.toml", "name = \"long\"\nreplicates = 1\ntests = []\nevaluations = 100_000_000_000\n"
                              "[[condition]]\nname = \"ME\"\nconfig = \"" +
                                  std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml\"\n");
  const fs::path log = scratch() / "locked-experiment-log";
  fs::remove_all(log);
  fs::create_directories(log);
  // `timeout`: without the lock, the second experiment would run its huge budget to the end.
  const std::string during =
      "timeout 60 " + kBinary + " experiment --config " + quote(experiment.string()) + " --out " + quote(out.string()) + " > " +
      quote((log / "experiment").string()) + " 2>&1; timeout 60 " + kBinary + " resume --out " + quote((out / "me/seed-1").string()) +
      " > " + quote((log / "resume").string()) + " 2>&1";
  while_stopped_at_checkpoint(
      kBinary + " experiment --quiet --threads 1 --config " + quote(experiment.string()) + " --out " + quote(out.string()),
      1, during, "INT");
  EXPECT_NE(slurp(log / "experiment").find("is in use by another qdmeta process"), std::string::npos)
      << slurp(log / "experiment");
  EXPECT_NE(slurp(log / "resume").find("is in use by another qdmeta process"), std::string::npos) << slurp(log / "resume");
}

// --- 7. Leftovers: the first checkpoint, a stray checkpoint, a refused resume.

TEST(Robustness, ARunKilledBeforeItsFirstPeriodicCheckpointResumesToTheSameBits) {
  const fs::path straight = fresh_dir("first-straight"), killed = fresh_dir("first-killed");
  const std::string config = quote(first_checkpoint_only_config().string());
  ASSERT_EQ(qdmeta_cli("run --config " + config + " --out " + quote(straight.string()) + " --quiet").status, 0);
  signalled_at_checkpoint(kBinary + " run --config " + config + " --out " + quote(killed.string()) + " --quiet --threads 1",
                          1, "KILL");
  ASSERT_TRUE(fs::exists(killed / "checkpoint.bin"));
  ASSERT_FALSE(fs::exists(killed / "summary.json")) << "finished before it was killed: raise the budget";
  const std::string checkpoint = slurp(killed / "checkpoint.bin");

  // 9. Every byte is under the checksum, the program version in the header too.
  std::string damaged = checkpoint;
  const auto version = damaged.find(QDMETA_VERSION);
  ASSERT_NE(version, std::string::npos);
  ASSERT_LT(version, 64u) << "the version is in the header";
  damaged[version] = static_cast<char>(damaged[version] ^ 0x01);
  std::ofstream(killed / "checkpoint.bin", std::ios::binary) << damaged;
  const Outcome refused = qdmeta_cli("resume --out " + quote(killed.string()) + " --quiet");
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find("damaged: checksum mismatch"), std::string::npos) << refused.output;
  std::ofstream(killed / "checkpoint.bin", std::ios::binary) << checkpoint;

  const Outcome resumed = qdmeta_cli("resume --out " + quote(killed.string()) + " --quiet --threads 2");
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  expect_same_run(straight, killed);

  // A finished run that still has a checkpoint (killed between its summary and the removal).
  std::ofstream(straight / "checkpoint.bin", std::ios::binary) << checkpoint;
  const Outcome stray = qdmeta_cli("resume --out " + quote(straight.string()));
  EXPECT_EQ(stray.status, 2) << stray.output;
  EXPECT_NE(stray.output.find("already finished"), std::string::npos) << stray.output;
  EXPECT_TRUE(fs::exists(straight / "checkpoint.bin")) << "a refused resume removed the leftover checkpoint";
}

TEST(Robustness, ARefusedResumeChangesNothing) {
  const fs::path dir = fresh_dir("refused-resume");
  const Outcome stopped = signalled_at_checkpoint(kBinary + " run --config " + quote(first_checkpoint_only_config().string()) +
                                                     " --out " + quote(dir.string()) + " --quiet --threads 1",
                                                 1, "INT");
  ASSERT_EQ(stopped.status, 130) << stopped.output;
  ASSERT_TRUE(fs::exists(dir / "summary.json"));
  fs::remove(dir / "metrics.csv");
  const Outcome o = qdmeta_cli("resume --out " + quote(dir.string()));
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("metrics.csv"), std::string::npos) << o.output;
  EXPECT_TRUE(fs::exists(dir / "summary.json")) << "a refused resume deleted summary.json";
  EXPECT_TRUE(fs::exists(dir / "checkpoint.bin"));
}

// --- 5. A directory is not a config.

TEST(Robustness, ADirectoryIsNotAConfig) {
  const std::string dir = quote(std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin");
  for (const std::string& command : {"run --config " + dir + " --out " + quote(fresh_dir("dir-config").string()),
                                     "experiment --config " + dir + " --out " + quote(fresh_dir("dir-exp").string())}) {
    const Outcome o = qdmeta_cli(command);
    EXPECT_EQ(o.status, 2) << command << "\n" << o.output;
    EXPECT_NE(o.output.find("is not a regular file"), std::string::npos) << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << o.output;
  }
}

// --- 6. adapt reads every value of the archive it tests, and CRLF files.

TEST(Robustness, AdaptRefusesBadArchiveValuesNamingLineColumnAndRule) {
  const fs::path dir = fresh_dir("adapt-values");
  ASSERT_EQ(qdmeta_cli("run --config " + map_elites_config() + " --out " + quote(dir.string()) + " --evals 20000 --quiet").status, 0);
  ASSERT_EQ(qdmeta_cli("adapt --run " + quote(dir.string()) + " --test dimension --budget 5 --quiet").status, 0);
  const std::string good = slurp(dir / "archive.csv");
  const std::string curve = slurp(dir / "adapt-dimension.csv");
  const std::size_t line2 = good.find('\n') + 1;
  const std::size_t line3 = good.find('\n', line2) + 1;
  std::vector<std::string> cells;
  {
    std::string cell;
    for (char c : good.substr(line2, line3 - line2 - 1)) {
      if (c != ',') {
        cell += c;
        continue;
      }
      cells.push_back(cell);
      cell.clear();
    }
    cells.push_back(cell);
  }
  // column (1-based), value, what the message must say
  struct Case {
    std::size_t column;
    std::string value, says;
  };
  const std::vector<Case> cases = {
      {2, "nan", "column 2 (objective): 'nan' is not finite"},
      {2, "inf", "column 2 (objective): 'inf' is not finite"},
      {2, "-1e300", "column 2 (objective): '-1e300' is out of range of a 32-bit float"},
      {3, "-inf", "column 3 (measures_0): '-inf' is not finite"},
      {5, "1.5", "column 5 (solution_0): 1.5 is outside [0, 1]"},
      {6, "-0.25", "column 6 (solution_1): -0.25 is outside [0, 1]"},
      {1, "-1", "column 1 (index): -1 is negative"},
      {1, "0.5", "column 1 (index): '0.5' is not a number"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> row = cells;
    row[c.column - 1] = c.value;
    std::string line;
    for (std::size_t i = 0; i < row.size(); ++i) line += (i ? "," : "") + row[i];
    std::ofstream(dir / "archive.csv", std::ios::binary) << good.substr(0, line2) + line + "\n" + good.substr(line3);
    const Outcome o = qdmeta_cli("adapt --run " + quote(dir.string()) + " --test dimension --budget 5 --quiet");
    EXPECT_EQ(o.status, 2) << c.value << "\n" << o.output;
    EXPECT_NE(o.output.find("archive.csv\":2: " + c.says), std::string::npos) << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << o.output;
  }
  // A file saved with Windows line endings reads the same.
  std::string crlf;
  for (char ch : good) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  std::ofstream(dir / "archive.csv", std::ios::binary) << crlf;
  fs::remove(dir / "adapt-dimension.csv");
  const Outcome o = qdmeta_cli("adapt --run " + quote(dir.string()) + " --test dimension --budget 5 --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_EQ(slurp(dir / "adapt-dimension.csv"), curve);
}

// --- 4. Memory is estimated before anything is allocated.

struct TooLarge {
  std::string config, key;
  bool terabytes;  // beyond any machine: refused without a ulimit too
};

std::vector<TooLarge> too_large_configs() {
  const std::string qd = "algorithm = \"qd-meta\"\n";
  return {
      {qd + "[control]\nkind = \"static\"\ngenerations = 1_000_000\n", "control.max_generations (or generations)", true},
      {qd + "[control]\nmax_generations = 1_000_000\n", "control.max_generations", true},
      {qd + "[qd_meta]\nhidden = 10_000\n", "qd_meta.hidden", true},
      {qd + "[qd_meta]\ndatabase_capacity = 1_000_000_000\n", "qd_meta.database_capacity", false},
      {qd + "[qd_meta]\nmeta_population = 10_000\n", "qd_meta.meta_population", false},
      {"[archive]\nbins = [10_000, 10_000]\n", "archive.bins", false},
      {"[map_elites]\nbatch_size = 10_000_000\n", "map_elites.batch_size", false},
      {"[map_elites]\ninitial_population = 100_000_000\n", "map_elites.initial_population", false},
      {"algorithm = \"cvt-map-elites\"\n[cvt]\nsamples = 1_000_000_000\ncache = false\n", "cvt.samples", false},
      {"algorithm = \"aurora\"\n[aurora]\nhidden = [100_000, 100_000]\n", "aurora.hidden", true},
  };
}

void expect_refused_for_memory(const std::string& prefix, const TooLarge& c, int i) {
  const fs::path config = write_file("memory-" + std::to_string(i) + ".toml", c.config);
  const Outcome o = shell(prefix + kBinary + " run --config " + quote(config.string()) + " --out " +
                          quote(fresh_dir("memory-" + std::to_string(i)).string()));
  EXPECT_EQ(o.status, 2) << c.config << "\n" << o.output;
  EXPECT_NE(o.output.find("of memory but"), std::string::npos) << c.config << "\n" << o.output;
  EXPECT_NE(o.output.find(c.key), std::string::npos) << c.config << "\n" << o.output;
  EXPECT_EQ(o.output.find("bad_alloc"), std::string::npos) << o.output;
  EXPECT_EQ(count_lines(o.output), 1) << o.output;
}

TEST(Robustness, AConfigBeyondAnyMachineIsRefusedBeforeAllocating) {
  int i = 0;
  for (const TooLarge& c : too_large_configs())
    if (c.terabytes) expect_refused_for_memory("", c, i++);
}

TEST(Robustness, AConfigBeyondTheUlimitIsRefusedNamingItsKeys) {
#ifdef QDMETA_SANITIZED
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: no ulimit -v under it";
#else
  int i = 100;
  for (const TooLarge& c : too_large_configs()) expect_refused_for_memory("ulimit -v 2000000; ", c, i++);
  // What fits still runs under the same limit.
  const Outcome fits = shell("ulimit -v 2000000; " + kBinary + " run --config " + map_elites_config() + " --out " +
                             quote(fresh_dir("memory-fits").string()) + " --evals 20000 --quiet");
  EXPECT_EQ(fits.status, 0) << fits.output;
#endif
}

// --- 4. A cache miss that costs minutes of k-means says so.

TEST(Robustness, KMeansOnACacheMissIsAnnounced) {
  const fs::path cache = fresh_dir("kmeans-cache");
  const fs::path config = write_file("kmeans.toml", "algorithm = \"cvt-map-elites\"\n[cvt]\ncentroids = 50\nsamples = 5000\n"
                                                    "init_samples = 1000\ncache_dir = \"" + cache.string() + "\"\n");
  const auto run = [&](const std::string& name) {
    return qdmeta_cli("run --config " + quote(config.string()) + " --out " + quote(fresh_dir(name).string()) +
                      " --evals 4000 --quiet");
  };
  const Outcome miss = run("kmeans-1");
  ASSERT_EQ(miss.status, 0) << miss.output;
  EXPECT_NE(miss.output.find("qdmeta: making 50 CVT centroids in 20 dimensions by k-means over 5000 uniform points (no "
                             "cache for these settings)"),
            std::string::npos)
      << miss.output;
  const Outcome hit = run("kmeans-2");
  ASSERT_EQ(hit.status, 0) << hit.output;
  EXPECT_EQ(hit.output.find("k-means"), std::string::npos) << hit.output;
}

// --- 8. What stands in a run directory in place of a file: not a regular file, a planted link.

// Replaces `file` by a FIFO, a link to /dev/zero or a directory.
void replace_by(const fs::path& file, const std::string& kind) {
  fs::remove(file);
  if (kind == "fifo") {
    ASSERT_EQ(shell("mkfifo " + quote(file.string())).status, 0);
  }
  if (kind == "device") fs::create_symlink("/dev/zero", file);
  if (kind == "directory") fs::create_directories(file / "inside");
}

TEST(Robustness, AFileThatIsNotARegularFileIsRefusedInOneLineNeverWaitedOnOrReadWhole) {
  const fs::path run = interrupted_run("not-regular-run");
  const fs::path finished = fresh_dir("not-regular-finished");
  ASSERT_EQ(qdmeta_cli("run --config " + map_elites_config() + " --out " + quote(finished.string()) +
                       " --evals 20000 --quiet").status, 0);
  struct Case {
    fs::path source;
    std::string file, command;
  };
  std::vector<Case> cases;
  for (const char* f : {"checkpoint.bin", "summary.json", "metrics.csv", "meta.csv", "config.toml"})
    cases.push_back({run, f, "resume --quiet --out "});
  for (const char* f : {"archive.csv", "summary.json", "config.toml"})
    cases.push_back({finished, f, "adapt --test dimension --budget 5 --quiet --run "});
  int i = 0;
  for (const Case& c : cases)
    for (const std::string kind : {"fifo", "device", "directory"}) {
      const fs::path dir = fresh_dir("not-regular-" + std::to_string(i++));
      fs::copy(c.source, dir, fs::copy_options::recursive);
      replace_by(dir / c.file, kind);
      // `timeout`: a FIFO used to hang resume and adapt forever.
      const Outcome o = shell("timeout 60 " + kBinary + " " + c.command + quote(dir.string()));
      EXPECT_EQ(o.status, 2) << c.file << " as " << kind << "\n" << o.output;
      EXPECT_EQ(count_lines(o.output), 1) << c.file << " as " << kind << "\n" << o.output;
      EXPECT_NE(o.output.find(c.file), std::string::npos) << c.file << " as " << kind << "\n" << o.output;
      EXPECT_EQ(o.output.find("memory"), std::string::npos) << o.output;
    }
}

TEST(Robustness, LinksPlantedInARunDirectoryAreReplacedNeverWrittenThrough) {
  const fs::path victim = write_file("victim.txt", "keep me");
  const auto expect_victim_kept = [&](const std::string& where) {
    EXPECT_EQ(slurp(victim), "keep me") << "written through a link at " << where;
  };
  // Before the run: a link where a temporary file used to go, and dangling links where the logs go.
  for (const std::string name : {"config.toml.tmp", "metrics.csv.tmp", "checkpoint.bin.tmp"}) {
    const fs::path dir = fresh_dir("planted-" + name);
    fs::create_directories(dir);
    fs::create_symlink(victim, dir / name);
    const Outcome o = qdmeta_cli("run --config " + map_elites_config() + " --out " + quote(dir.string()) +
                                 " --evals 20000 --quiet");
    EXPECT_EQ(o.status, 0) << o.output;
    expect_victim_kept(name);
  }
  for (const std::string name : {"metrics.csv", "meta.csv", "archive.csv", "summary.json", "checkpoint.bin"}) {
    const fs::path dir = fresh_dir("dangling-" + name);
    fs::create_directories(dir);
    const fs::path elsewhere = scratch() / ("elsewhere-" + name);
    fs::remove(elsewhere);
    fs::create_symlink(elsewhere, dir / name);
    const Outcome refused = qdmeta_cli("run --config " + map_elites_config() + " --out " + quote(dir.string()) +
                                       " --evals 20000 --quiet");
    EXPECT_EQ(refused.status, 2) << name << ": a link there is a run file there\n" << refused.output;
    EXPECT_NE(refused.output.find("already holds a run"), std::string::npos) << refused.output;
    EXPECT_EQ(qdmeta_cli("run --config " + map_elites_config() + " --out " + quote(dir.string()) +
                         " --evals 20000 --quiet --overwrite").status, 0);
    EXPECT_FALSE(fs::exists(elsewhere)) << "a run created " << name << " through a dangling link";
    EXPECT_FALSE(fs::is_symlink(dir / name)) << name;
  }
  // During the run: links planted where its last files go, while it is stopped at a checkpoint.
  const fs::path dir = fresh_dir("planted-during");
  const std::string plant = "for f in archive.csv summary.json checkpoint.bin; do rm -f " + quote(dir.string()) +
                            "/$f; ln -s " + quote(victim.string()) + " " + quote(dir.string()) + "/$f; done";
  const Outcome o = while_stopped_at_checkpoint(kBinary + " run --config " + quote(first_checkpoint_only_config().string()) +
                                                    " --out " + quote(dir.string()) + " --quiet --threads 1",
                                                1, plant, "INT");
  EXPECT_EQ(o.status, 130) << o.output;
  expect_victim_kept("archive.csv, summary.json or checkpoint.bin");
  for (const char* f : {"archive.csv", "summary.json", "checkpoint.bin"}) EXPECT_FALSE(fs::is_symlink(dir / f)) << f;
  ASSERT_EQ(qdmeta_cli("resume --quiet --out " + quote(dir.string())).status, 0);
  // The test phase's files.
  for (const char* f : {"adapt-dimension.csv", "adapt-dimension.csv.tmp"}) fs::create_symlink(victim, dir / f);
  const Outcome adapt = qdmeta_cli("adapt --run " + quote(dir.string()) + " --test dimension --budget 5 --quiet");
  EXPECT_EQ(adapt.status, 0) << adapt.output;
  expect_victim_kept("adapt-dimension.csv");
  EXPECT_FALSE(fs::is_symlink(dir / "adapt-dimension.csv"));
}

// --- 9. Configs that the TOML parser alone would misread or crash on.

TEST(Robustness, ANulByteOrKeysNestedTooDeepAreRefusedInOneLine) {
  static constexpr char kNulConfig[] = "seed = 2\n\0algorithm = \"aurora\"\n";
  std::string header = "[a", dotted = "a";
  for (int i = 0; i < 100'000; ++i) {
    header += ".a";
    dotted += ".a";
  }
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/proc/self/environ", "a NUL byte"},  // stopped at its first NUL, it used to run as "all defaults"
      {write_file("nul.toml", std::string(kNulConfig, sizeof kNulConfig - 1)).string(), "nul.toml:2:1: a NUL byte"},
      {write_file("deep-header.toml", header + "]\n").string(), "a key or table header of more than 32 parts"},
      {write_file("deep-key.toml", dotted + " = 1\n").string(), "a key or table header of more than 32 parts"},
      {write_file("deep-array.toml", "x = " + std::string(100'000, '[') + "\n").string(), "nested more than 32 deep"},
  };
  for (const auto& [config, says] : cases) {
    for (const char* command : {"run --quiet --evals 1000 --out ", "experiment --out "}) {
      const Outcome o = qdmeta_cli(std::string(command) + quote(fresh_dir("nul-out").string()) + " --config " +
                                   quote(config));
      EXPECT_EQ(o.status, 2) << config.substr(0, 80) << "\n" << o.output.substr(0, 500);
      EXPECT_NE(o.output.find(says), std::string::npos) << o.output.substr(0, 500);
      EXPECT_EQ(count_lines(o.output), 1) << o.output.substr(0, 500);
    }
  }
}

// --- 10. Late checks: a resume reads back every kept row; library text never reaches the user.

TEST(Robustness, AResumeRefusesLogsChangedSinceTheCheckpointAndChangesNothing) {
  const fs::path run = interrupted_run("changed-logs-run");
  for (const char* file : {"metrics.csv", "meta.csv"}) {
    const fs::path dir = fresh_dir(std::string("changed-") + file);
    fs::copy(run, dir, fs::copy_options::recursive);
    // One digit of a kept row changed: the file keeps its length, only its content differs.
    std::string text = slurp(dir / file);
    const std::size_t digit = text.find_first_of("123456789", text.find('\n') + 1);
    ASSERT_NE(digit, std::string::npos) << text;
    text[digit] = text[digit] == '9' ? '8' : static_cast<char>(text[digit] + 1);
    std::ofstream(dir / file, std::ios::binary) << text;
    const std::string checkpoint = slurp(dir / "checkpoint.bin");
    const Outcome o = qdmeta_cli("resume --quiet --out " + quote(dir.string()));
    EXPECT_EQ(o.status, 2) << file << "\n" << o.output;
    EXPECT_NE(o.output.find(file), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("differ from those the checkpoint saw"), std::string::npos) << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << o.output;
    EXPECT_EQ(slurp(dir / "checkpoint.bin"), checkpoint);
    EXPECT_EQ(slurp(dir / file), text);
    EXPECT_TRUE(fs::exists(dir / "summary.json"));
  }
}

TEST(Robustness, AnImpossibleTestBudgetIsRefusedInTheProgramsOwnWords) {
  const fs::path dir = fresh_dir("huge-budget");
  ASSERT_EQ(qdmeta_cli("run --config " + map_elites_config() + " --out " + quote(dir.string()) + " --evals 20000 --quiet")
                .status,
            0);
  for (const char* budget : {"9223372036854775807", "100000000"}) {
    const Outcome o = qdmeta_cli("adapt --run " + quote(dir.string()) + " --test dimension --quiet --budget " + budget);
    EXPECT_EQ(o.status, 2) << o.output;
    EXPECT_NE(o.output.find(std::string("budget ") + budget + " is more than its curves can hold"), std::string::npos)
        << o.output;
    EXPECT_EQ(o.output.find("max_size"), std::string::npos) << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << o.output;
  }
}

// --- 11. Runs side by side, as a SLURM array on a cold cache or two test phases of one run.

TEST(Robustness, RunsAndTestPhasesSideBySideShareNoTemporaryFile) {
  const fs::path cache = fresh_dir("shared-cache");
  const fs::path config = write_file("cvt-shared.toml", "algorithm = \"cvt-map-elites\"\n[cvt]\ncentroids = 200\n"
                                                        "samples = 20000\ncache_dir = \"" + cache.string() + "\"\n");
  std::string together;
  for (int i = 0; i < 4; ++i)
    together += kBinary + " run --quiet --threads 1 --evals 2000 --config " + quote(config.string()) + " --out " +
                quote(fresh_dir("side-by-side-" + std::to_string(i)).string()) + " > " +
                quote((scratch() / ("side-" + std::to_string(i))).string()) + " 2>&1 & p" + std::to_string(i) + "=$!; ";
  ASSERT_EQ(shell(together + "wait $p0 && wait $p1 && wait $p2 && wait $p3").status, 0)
      << slurp(scratch() / "side-0") << slurp(scratch() / "side-1") << slurp(scratch() / "side-2")
      << slurp(scratch() / "side-3");
  const fs::path dir = fresh_dir("side-by-side-0");
  ASSERT_EQ(qdmeta_cli("run --config " + map_elites_config() + " --out " + quote(dir.string()) + " --evals 20000 --quiet")
                .status,
            0);
  const std::string adapt = kBinary + " adapt --quiet --test dimension --budget 50 --run " + quote(dir.string());
  EXPECT_EQ(shell(adapt + " & p0=$!; " + adapt + " & p1=$!; " + adapt + " & p2=$!; wait $p0 && wait $p1 && wait $p2").status,
            0);
  EXPECT_EQ(count_lines(slurp(dir / "adapt-dimension.csv")), 51);
}

}  // namespace
}  // namespace qdmeta
