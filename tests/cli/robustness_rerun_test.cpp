// The command line after an interruption (issue 42): a refused resume changes no file, an
// experiment run again after its configs changed, what a writer killed by the file size limit
// leaves, every message one line. Each test here failed before its fix.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "robustness_helpers.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

using namespace robustness;  // NOLINT(google-build-using-namespace): the shared helpers of these tests
using cli_test::slurp;

// Every entry of `dir` (not recursive): a file's bytes, a link's target, or "directory".
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> entries;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_symlink()) entries[name] = "link to " + fs::read_symlink(e.path()).string();
    else if (e.is_directory()) entries[name] = "directory";
    else entries[name] = slurp(e.path());
  }
  return entries;
}

// --- A refused resume changes no file, summary.json included.

TEST(RobustnessRerun, ARefusedResumeLeavesEveryFileAsItWas) {
  const fs::path run = interrupted_run("refusals-run");
  ASSERT_TRUE(fs::exists(run / "summary.json"));
  struct Refusal {
    std::string name;
    std::string expected;  // in the one line of the refusal
    void (*damage)(const fs::path& dir);
  };
  const std::vector<Refusal> refusals = {
      {"metrics-link", "is a symbolic link",
       [](const fs::path& dir) {
         fs::copy_file(dir / "metrics.csv", dir / "metrics-copy.csv");
         fs::remove(dir / "metrics.csv");
         fs::create_symlink("metrics-copy.csv", dir / "metrics.csv");
       }},
      {"meta-link", "is a symbolic link",
       [](const fs::path& dir) {
         fs::copy_file(dir / "meta.csv", dir / "meta-copy.csv");
         fs::remove(dir / "meta.csv");
         fs::create_symlink(fs::absolute(dir / "meta-copy.csv"), dir / "meta.csv");
       }},
      {"metrics-gone", "metrics.csv", [](const fs::path& dir) { fs::remove(dir / "metrics.csv"); }},
      {"metrics-cut", "metrics.csv", [](const fs::path& dir) { fs::resize_file(dir / "metrics.csv", 10); }},
      {"checkpoint-damaged", "checksum",
       [](const fs::path& dir) {
         std::string bytes = slurp(dir / "checkpoint.bin");
         bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 1);
         std::ofstream(dir / "checkpoint.bin", std::ios::binary) << bytes;
       }},
  };
  for (const Refusal& refusal : refusals) {
    const fs::path dir = fresh_dir("refusal-" + refusal.name);
    fs::copy(run, dir, fs::copy_options::recursive);
    refusal.damage(dir);
    const auto before = snapshot(dir);
    const Outcome o = qdmeta_cli("resume --quiet --out " + quote(dir.string()));
    EXPECT_EQ(o.status, 2) << refusal.name << "\n" << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << refusal.name << "\n" << o.output;
    EXPECT_NE(o.output.find(refusal.expected), std::string::npos) << refusal.name << "\n" << o.output;
    EXPECT_EQ(snapshot(dir), before) << refusal.name << ": the refused resume changed the directory";
  }
}


// --- An experiment run again after a condition changed: refused, naming the run and the keys.

// The experiment of the issue: three replicates of one MAP-Elites condition, its config beside it.
struct SmallExperiment {
  fs::path dir;
  fs::path file;    // the experiment file
  fs::path config;  // the condition's config

  explicit SmallExperiment(const std::string& name) : dir(fresh_dir(name)) {
    fs::create_directories(dir);
    file = dir / "experiment.toml";
    config = dir / "me.toml";
    set_sigma("0.05");
    set_experiment("");
  }
  void set_sigma(const std::string& sigma) const {
    std::ofstream(config) << "algorithm = \"map-elites\"\n[mutation]\nsigma = " + sigma + "\n";
  }
  void set_experiment(const std::string& set) const {
    std::ofstream(file) << "name = \"rerun\"\nreplicates = 3\ntests = []\n[[condition]]\nname = \"ME\"\n"
                           "config = \"me.toml\"\n" + set;
  }
  Outcome run(const std::string& args) const {
    return qdmeta_cli("experiment --config " + quote(file.string()) + " --out " + quote((dir / "out").string()) +
                      " --evals 20000 --quiet --no-report " + args);
  }
  fs::path seed(int r) const { return dir / "out" / "me" / ("seed-" + std::to_string(r)); }
};

// The sigma and the fingerprint a run's config.toml records.
std::string recorded(const fs::path& run, const std::string& key) {
  const std::string text = slurp(run / "config.toml");
  const std::size_t at = text.find("\n" + key + " = ");
  if (at == std::string::npos) return "";
  const std::size_t from = at + key.size() + 4;
  return text.substr(from, text.find('\n', from) - from);
}

TEST(RobustnessRerun, AnExperimentRunAgainAfterItsConfigChangedIsRefusedNamingTheRunAndKeys) {
  const SmallExperiment e("rerun-changed");
  ASSERT_EQ(e.run("--seeds 1").status, 0);  // the state a kill after seed 1's test phase leaves
  const auto before = snapshot(e.seed(1));
  const auto refused = [&](const std::string& why) {
    const Outcome o = e.run("");
    EXPECT_EQ(o.status, 2) << why << "\n" << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << why << "\n" << o.output;
    EXPECT_NE(o.output.find(e.seed(1).string()), std::string::npos) << why << "\n" << o.output;
    EXPECT_NE(o.output.find("mutation.sigma differs"), std::string::npos) << why << "\n" << o.output;
    EXPECT_NE(o.output.find("--restart-changed"), std::string::npos) << why << "\n" << o.output;
    EXPECT_FALSE(fs::exists(e.seed(2))) << why << ": the refused call ran another replicate";
    EXPECT_EQ(snapshot(e.seed(1)), before) << why;
  };
  e.set_sigma("0.2");
  refused("the config edited");
  e.set_sigma("0.05");
  e.set_experiment("set = { mutation = { sigma = 0.3 } }\n");
  refused("a set added to the experiment file");
  e.set_experiment("");
  const Outcome same = e.run("");  // back as it was: the kept run is the condition's
  ASSERT_EQ(same.status, 0) << same.output;
  EXPECT_EQ(snapshot(e.seed(1)), before);

  e.set_experiment("set = { mutation = { sigma = 0.3 } }\n");
  const Outcome restarted = e.run("--restart-changed");
  ASSERT_EQ(restarted.status, 0) << restarted.output;
  const std::string fingerprint = recorded(e.seed(1), "config_fingerprint");
  EXPECT_EQ(fingerprint.size(), 18u) << fingerprint;  // 16 hex digits, quoted
  for (int r = 1; r <= 3; ++r) {
    EXPECT_EQ(recorded(e.seed(r), "sigma"), "0.29999999999999999") << r;
    EXPECT_EQ(recorded(e.seed(r), "config_fingerprint"), fingerprint) << r;
  }
  EXPECT_EQ(e.run("").status, 0);  // nothing changed since: every run kept
}

TEST(RobustnessRerun, APlanRowOfAnotherConfigIsRefusedAndTheRunsItsTasksMakeAgree) {
  const SmallExperiment e("rerun-plan");
  ASSERT_EQ(e.run("--plan").status, 0);
  const std::string plan = slurp(e.dir / "out" / "plan.tsv");
  EXPECT_TRUE(plan.starts_with("index\tcondition\tseed\tconfig\tdir\tconfig_fingerprint\n")) << plan;
  // A batch task runs line 1 as the plan says; its run records the plan's fingerprint.
  ASSERT_EQ(qdmeta_cli("run --quiet --config " + quote((e.dir / "out" / "me" / "condition.toml").string()) +
                       " --seed 1 --out " + quote(e.seed(1).string()))
                .status,
            0);
  const std::string fingerprint = recorded(e.seed(1), "config_fingerprint");
  EXPECT_NE(plan.find("\t" + fingerprint.substr(1, 16) + "\n"), std::string::npos) << plan << fingerprint;
  fs::remove_all(e.seed(1));
  e.set_sigma("0.2");
  const Outcome o = e.run("--plan");
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_EQ(count_lines(o.output), 1) << o.output;
  EXPECT_NE(o.output.find("plan.tsv: row 1 (me seed 1) was planned with another config"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("mutation.sigma differs"), std::string::npos) << o.output;
  EXPECT_EQ(slurp(e.dir / "out" / "plan.tsv"), plan);
  // Run by the experiment itself, the plan would still give its tasks the old config.
  const Outcome unplanned = e.run("--restart-changed");
  EXPECT_EQ(unplanned.status, 2) << unplanned.output;
  EXPECT_NE(unplanned.output.find("plan.tsv: row 1"), std::string::npos) << unplanned.output;
  ASSERT_EQ(e.run("--plan --restart-changed").status, 0);
  EXPECT_NE(slurp(e.dir / "out" / "plan.tsv"), plan);
}

// A stand-in for tools/run_summary.py (numpy-free): the run's summary.json and the fingerprint of
// its config.toml, as the summary writer is to keep them (top-level "config_fingerprint").
fs::path summary_tools() {
  const fs::path tools = fresh_dir("summary-tools");
  fs::create_directories(tools);
  std::ofstream(tools / "run_summary.py")
      << "import json, os, re, sys\n"
         "run, target = sys.argv[1], sys.argv[2]\n"
         "os.makedirs(os.path.dirname(target), exist_ok=True)\n"
         "summary = json.load(open(run + '/summary.json'))\n"
         "fingerprint = re.search(r\"config_fingerprint = '([0-9a-f]+)'\", open(run + '/config.toml').read()).group(1)\n"
         "json.dump({'summary': summary, 'config': {'algorithm': 'map-elites'}, 'config_fingerprint': fingerprint},"
         " open(target, 'w'))\n";
  return tools;
}

TEST(RobustnessRerun, AKeptSummaryOfAnotherConfigIsRefusedAndALegacyOneCheckedAsBefore) {
  const SmallExperiment e("rerun-summaries");
  const fs::path summaries = e.dir / "summaries";
  const std::string with_tools = "QDMETA_TOOLS_DIR=" + quote(summary_tools().string()) + " ";
  const auto run = [&](const std::string& args) {
    return shell(with_tools + kBinary + " experiment --config " + quote(e.file.string()) + " --out " +
                 quote((e.dir / "out").string()) + " --evals 20000 --quiet --no-report --summaries " +
                 quote(summaries.string()) + " " + args);
  };
  ASSERT_EQ(run("--seeds 1").status, 0);
  const fs::path kept = summaries / "me" / "seed-1.json";
  ASSERT_TRUE(fs::exists(kept));
  fs::remove_all(e.dir / "out");  // the summary is kept, its run directory on another machine
  e.set_sigma("0.2");
  const Outcome o = run("");
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_EQ(count_lines(o.output), 1) << o.output;
  EXPECT_NE(o.output.find(kept.string() + " was made with another config than condition 'ME'"), std::string::npos)
      << o.output;
  EXPECT_FALSE(fs::exists(e.seed(2)));
  // A summary written before fingerprints is checked by config name, set and budget only.
  std::string legacy = slurp(kept);
  const std::size_t at = legacy.find(", \"config_fingerprint\"");  // the last key
  ASSERT_NE(at, std::string::npos) << legacy;
  legacy.erase(at, legacy.rfind('}') - at);
  std::ofstream(kept) << legacy;
  ASSERT_EQ(run("--seeds 1").status, 0) << "a legacy summary was refused";
  e.set_experiment("set = { mutation = { sigma = 0.3 } }\n");
  const Outcome set = run("--seeds 1");
  EXPECT_EQ(set.status, 2) << set.output;
  EXPECT_NE(set.output.find("another set"), std::string::npos) << set.output;
  // Started over: made again under the condition in force.
  ASSERT_EQ(run("--seeds 1 --restart-changed").status, 0);
  EXPECT_NE(slurp(kept), legacy);
  EXPECT_EQ(recorded(e.seed(1), "sigma"), "0.29999999999999999");
}

// The summaries committed before fingerprints (docs/results/) are kept by the legacy rule.
TEST(RobustnessRerun, TheCommittedSummariesWithoutAFingerprintAreStillKept) {
  const fs::path source = fs::path(QDMETA_SOURCE_DIR) / "docs/results/rastrigin/100m/stated-sd/summaries";
  const fs::path kept = fresh_dir("committed-summaries"), out = fresh_dir("committed-plan");
  fs::copy(source, kept, fs::copy_options::recursive);
  const Outcome o = qdmeta_cli("experiment --plan --evals 100000000 --replicates 10 --config " +
                               quote((fs::path(QDMETA_SOURCE_DIR) / "configs/rastrigin/experiment-stated-sd.toml").string()) +
                               " --summaries " + quote(kept.string()) + " --out " + quote(out.string()));
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("0 runs planned"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("(40 more are done"), std::string::npos) << o.output;
}

// --- Ctrl-C in the report phase: exit 130 and one line, never the script's traceback.

TEST(RobustnessRerun, CtrlCDuringTheReportEndsTheExperimentAsInterrupted) {
  const SmallExperiment e("interrupted-report");
  const fs::path python = write_file("ctrl-c-python.sh",
                                     "#!/bin/sh\n# Ctrl-C reaches the whole process group: qdmeta and its script.\n"
                                     "kill -INT $PPID\necho 'Traceback (most recent call last):' >&2\n"
                                     "echo 'KeyboardInterrupt' >&2\nexit 130\n");
  fs::permissions(python, fs::perms::owner_exec, fs::perm_options::add);
  const Outcome o = shell("QDMETA_PYTHON=" + quote(python.string()) + " " + kBinary + " experiment --config " +
                          quote(e.file.string()) + " --out " + quote((e.dir / "out").string()) +
                          " --evals 20000 --seeds 1");
  EXPECT_EQ(o.status, 130) << o.output;
  EXPECT_EQ(o.output.find("Traceback"), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find("error"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("interrupted: run the same command again to continue\n"), std::string::npos) << o.output;
}

TEST(RobustnessRerun, CtrlCDuringAPlainReportEndsAsInterrupted) {
  const fs::path dir = fresh_dir("interrupted-plain-report");
  fs::create_directories(dir);
  std::ofstream(dir / "experiment.toml") << "name = \"x\"\n";
  const fs::path python = write_file("ctrl-c-report-python.sh",
                                     "#!/bin/sh\nkill -INT $PPID\necho 'report.py: interrupted' >&2\nexit 130\n");
  fs::permissions(python, fs::perms::owner_exec, fs::perm_options::add);
  const Outcome o = shell("QDMETA_PYTHON=" + quote(python.string()) + " " + kBinary + " report " + quote(dir.string()));
  EXPECT_EQ(o.status, 130) << o.output;
  EXPECT_EQ(o.output, "interrupted: run the same command again to make the report\n");
}

// --- Every message one line, of bounded length, whatever the values quoted in it hold.

TEST(RobustnessRerun, EveryMessageIsOneBoundedLine) {
  const auto one_bounded_line = [](const Outcome& o, const std::string& why) {
    EXPECT_EQ(o.status, 2) << why << "\n" << o.output.substr(0, 2000);
    EXPECT_EQ(count_lines(o.output), 1) << why << "\n" << o.output.substr(0, 2000);
    EXPECT_TRUE(o.output.starts_with("qdmeta: error: ")) << why << "\n" << o.output.substr(0, 2000);
    EXPECT_LE(o.output.size(), 8300u) << why;
  };
  const fs::path value = write_file("newline-value.toml", "algorithm = \"map\\nelites\\u001b[2J\"\n");
  one_bounded_line(qdmeta_cli("run --config " + quote(value.string()) + " --out " + quote(fresh_dir("nl-value").string())),
                   "a newline in a string value");
  const fs::path key = write_file("newline-key.toml", "\"bad\\nkey\" = 1\n");
  one_bounded_line(qdmeta_cli("run --config " + quote(key.string()) + " --out " + quote(fresh_dir("nl-key").string())),
                   "a newline in a key");
  one_bounded_line(qdmeta_cli("resume --out " + quote((scratch() / "no\nsuch\nrun").string())), "a newline in a path");
  const fs::path huge = write_file("huge-value.toml", "algorithm = \"" + std::string(50'000'000, 'x') + "\"\n");
  const Outcome o = qdmeta_cli("run --config " + quote(huge.string()) + " --out " + quote(fresh_dir("huge").string()));
  one_bounded_line(o, "a 50 MB value");
  EXPECT_NE(o.output.find("x...x"), std::string::npos) << o.output.substr(0, 200);
  fs::remove(huge);
}

// --- What a writer killed by the file size limit leaves, and what the next writer removes.

TEST(RobustnessRerun, AWriteBeyondTheFileSizeLimitEndsInOneLineAndResumesToTheSameBits) {
  // archive.csv (2.4 MB) passes the limit, no checkpoint (1 MB, after every step) does.
  const fs::path config = write_file("file-size.toml", "algorithm = \"map-elites\"\n[budget]\nevaluations = 300_000\n"
                                                       "[checkpoint]\nevery_seconds = 0\n");
  const fs::path straight = fresh_dir("file-size-straight"), limited = fresh_dir("file-size-limited");
  const std::string run = kBinary + " run --quiet --config " + quote(config.string()) + " --out ";
  ASSERT_EQ(shell(run + quote(straight.string())).status, 0);
  ASSERT_GT(fs::file_size(straight / "archive.csv"), 1500u * 1024);
  const Outcome o = shell("bash -c " + quote("ulimit -f 1500; exec " + run + quote(limited.string())));
  EXPECT_EQ(o.status, 2) << o.output;  // not 153: killed by SIGXFSZ
  EXPECT_EQ(count_lines(o.output), 1) << o.output;
  EXPECT_NE(o.output.find("the file size limit (ulimit -f) was reached"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("qdmeta resume --out"), std::string::npos) << o.output;
  for (const auto& e : fs::directory_iterator(limited))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path() << " left behind";
  const Outcome resumed = qdmeta_cli("resume --quiet --out " + quote(limited.string()));
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  cli_test::expect_same_run(straight, limited);
}

TEST(RobustnessRerun, TheNextWriterRemovesTheTemporariesOfADeadOne) {
  const fs::path dir = interrupted_run("dead-writer");
  // What a writer killed between creating and renaming its temporaries leaves (kill -9, SIGXFSZ
  // before it was ignored, the directory renamed under it): another process's, by their names.
  std::ofstream(dir / "archive.csv.tmp-999999-2") << std::string(2'400'000, 'x');
  std::ofstream(dir / "checkpoint.bin.tmp-1-0") << "partial";
  std::ofstream(dir / "notes.tmp-mine") << "not a temporary of qdmeta's";
  const Outcome o = qdmeta_cli("resume --quiet --out " + quote(dir.string()));
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_FALSE(fs::exists(dir / "archive.csv.tmp-999999-2"));
  EXPECT_FALSE(fs::exists(dir / "checkpoint.bin.tmp-1-0"));
  EXPECT_TRUE(fs::exists(dir / "notes.tmp-mine"));
}

TEST(RobustnessRerun, ARunDirectoryTooLongForItsFilesIsRefusedBeforeAnythingIsMade) {
  const fs::path top = fresh_dir("long-path");
  fs::path out = top;
  while (out.native().size() < 4000)  // config.toml fits below PATH_MAX, not its temporary's name
    out /= std::string(std::min<std::size_t>(200, 4000 - out.native().size()), 'd');
  for (const std::string& command : {"run --quiet --config " + map_elites_config() + " --evals 2000 --out ",
                                    "experiment --quiet --no-report --evals 2000 --seeds 1 --config " +
                                        quote((fs::path(QDMETA_SOURCE_DIR) / "configs/rastrigin/experiment.toml").string()) +
                                        " --out "}) {
    const Outcome o = qdmeta_cli(command + quote(out.string()));
    EXPECT_EQ(o.status, 2) << o.output.substr(0, 300);
    EXPECT_EQ(count_lines(o.output), 1) << o.output.substr(0, 300);
    EXPECT_NE(o.output.find("too long a path for a run"), std::string::npos) << o.output.substr(0, 300);
    EXPECT_FALSE(fs::exists(top)) << "a refused run left an empty directory behind";
  }
}

// --- adapt tests only what a run wrote: its resolved config, one elite per cell.

TEST(RobustnessRerun, AdaptRefusesAnEmptiedConfigAndDuplicateCells) {
  const fs::path run = fresh_dir("adapt-checks-run");
  ASSERT_EQ(qdmeta_cli("run --quiet --evals 20000 --config " + map_elites_config() + " --out " + quote(run.string())).status, 0);
  const auto adapt = [](const fs::path& dir) {
    return qdmeta_cli("adapt --quiet --test dimension --budget 5 --run " + quote(dir.string()));
  };
  ASSERT_EQ(adapt(run).status, 0);
  const std::string config = slurp(run / "config.toml");
  const std::vector<std::pair<std::string, std::string>> configs = {
      {"", "is not the resolved config of a run"},
      {"seed = 3\n", "is not the resolved config of a run"},
      {"bogus = 1\n" + config, "bogus"},
  };
  for (const auto& [text, expected] : configs) {
    const fs::path dir = fresh_dir("adapt-config");
    fs::copy(run, dir, fs::copy_options::recursive);
    fs::remove(dir / "adapt-dimension.csv");
    std::ofstream(dir / "config.toml") << text;
    const Outcome o = adapt(dir);
    EXPECT_EQ(o.status, 2) << text << "\n" << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << o.output;
    EXPECT_NE(o.output.find(expected), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(dir / "adapt-dimension.csv")) << text;
  }
  const fs::path dir = fresh_dir("adapt-duplicates");
  fs::copy(run, dir, fs::copy_options::recursive);
  std::string archive = slurp(dir / "archive.csv");
  const std::size_t first = archive.find('\n') + 1;
  const std::string row = archive.substr(first, archive.find('\n', first) + 1 - first);
  for (int i = 0; i < 5000; ++i) archive += row;
  std::ofstream(dir / "archive.csv") << archive;
  const Outcome o = adapt(dir);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("repeats line 2: a run's archive holds one elite per cell"), std::string::npos) << o.output;
}

}  // namespace
}  // namespace qdmeta
