// The MPI evaluator end to end, through `mpirun -np N qdmeta run ...` on localhost: the same
// bits with 1, 2 and 3 ranks as with threads, and a worker killed (or hung) mid-run stops the
// run with a one-line error naming it and a checkpoint that `qdmeta resume` finishes to the same
// bits, found by rank 0 itself whatever the launcher's kill timeout.
// Skipped (with the reason) when qdmeta was built without MPI or mpirun is missing.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_helpers.hpp"

namespace {

namespace fs = std::filesystem;

using qdmeta::cli_test::Outcome;
using qdmeta::cli_test::shell;
using qdmeta::cli_test::slurp;

fs::path scratch() { return qdmeta::cli_test::process_scratch("mpi_test"); }

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = scratch() / name;
  fs::remove_all(dir);
  return dir;
}

// Why MPI tests cannot run here, or "" when they can.
std::string unavailable() {
#ifndef QDMETA_MPIEXEC
  return "qdmeta was built without MPI (QDMETA_WITH_MPI=OFF)";
#else
  if (!fs::exists(QDMETA_MPIEXEC)) return std::string("no MPI launcher at ") + QDMETA_MPIEXEC + " (install openmpi-bin)";
#ifdef QDMETA_SANITIZED
  // Not yet verified under AddressSanitizer (OpenMPI's memory hooks and shared-memory transport
  // are not instrumented); opt in with QDMETA_MPI_SANITIZER_TESTS=1 (LSan suppressions are wired).
  if (const char* opt = std::getenv("QDMETA_MPI_SANITIZER_TESTS"); opt == nullptr || std::string(opt) != "1")
    return "sanitizer build: MPI tests are opt-in (QDMETA_MPI_SANITIZER_TESTS=1), see tests/lsan-openmpi.supp";
#endif
  return "";
#endif
}

// `mpirun -np N qdmeta ARGS` on this machine: shared memory between ranks, more ranks than
// cores allowed, and OpenMPI's consent to run as root (CI containers run as root).
std::string mpirun_command(int ranks, const std::string& args, const std::string& env,
                           const std::string& binary = QDMETA_BINARY) {
#ifdef QDMETA_MPIEXEC
  const std::string root = geteuid() == 0 ? "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " : "";
  // LeakSanitizer would report OpenMPI's own allocations (sanitizer builds only).
  const std::string lsan = "LSAN_OPTIONS=suppressions=" + std::string(QDMETA_SOURCE_DIR) + "/tests/lsan-openmpi.supp ";
  // `timeout`: a rank 0 that waits for a dead rank must fail the test, not hang it.
  return root + lsan + env + " timeout -k 5 120 " + QDMETA_MPIEXEC + " --oversubscribe --mca btl self,vader -np " +
         std::to_string(ranks) + " " + binary + " " + args;
#else
  (void)ranks, (void)args, (void)env, (void)binary;
  return "false";
#endif
}

Outcome mpirun(int ranks, const std::string& args, const std::string& env = "",
               const std::string& binary = QDMETA_BINARY) {
  return shell(mpirun_command(ranks, args, env, binary));
}

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Whether a qdmeta rank whose command line names `dir` is still running (mpirun's own command
// line starts with mpirun, the shell's with sh, so the anchor leaves them out).
std::string rank_pattern(const fs::path& dir) {
  return "'^" + std::string(QDMETA_BINARY) + " run .*" + dir.string() + "'";
}
bool ranks_alive(const fs::path& dir) { return shell("pgrep -f -- " + rank_pattern(dir)).status == 0; }
int ranks_running(const fs::path& dir) {
  const Outcome o = shell("pgrep -c -f -- " + rank_pattern(dir));
  return o.output.empty() ? 0 : std::atoi(o.output.c_str());
}

Outcome qdmeta_cli(const std::string& args) { return shell(std::string(QDMETA_BINARY) + " " + args); }

std::string config() { return std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml"; }

void expect_same_files(const fs::path& a, const fs::path& b) {
  for (const char* f : {"metrics.csv", "archive.csv"}) {
    ASSERT_TRUE(fs::exists(b / f)) << b / f;
    EXPECT_EQ(slurp(a / f), slurp(b / f)) << f << " differs between " << a << " and " << b;
  }
}

TEST(Mpi, OneTwoAndThreeRanksGiveTheBitsOfAThreadRun) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + config() + " --evals 20000 --seed 7 --quiet --out ";
  const fs::path threads = fresh_dir("threads");
  ASSERT_EQ(qdmeta_cli(run + threads.string() + " --threads 2").status, 0);
  for (int ranks : {1, 2, 3}) {
    const fs::path dir = fresh_dir("ranks" + std::to_string(ranks));
    const Outcome o = mpirun(ranks, run + dir.string());
    ASSERT_EQ(o.status, 0) << o.output;
    EXPECT_EQ(o.output, "") << "a quiet run prints nothing, on any rank";
    expect_same_files(threads, dir);
  }
}

// CMA-MAE's emitters ask on rank 0 only; the ranks evaluate their batches.
TEST(Mpi, CmaMaeOnThreeRanksGivesTheBitsOfAThreadRun) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + std::string(QDMETA_SOURCE_DIR) +
                          "/configs/rastrigin/cma-mae.toml --evals 30000 --quiet --out ";
  const fs::path threads = fresh_dir("cma-mae-threads"), ranks = fresh_dir("cma-mae-ranks");
  ASSERT_EQ(qdmeta_cli(run + threads.string() + " --threads 2").status, 0);
  const Outcome o = mpirun(3, run + ranks.string());
  ASSERT_EQ(o.status, 0) << o.output;
  expect_same_files(threads, ranks);
}

TEST(Mpi, TheHeaderNamesTheRanksAndOnlyRankZeroWrites) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const fs::path dir = fresh_dir("header");
  const Outcome o = mpirun(3, "run --config " + config() + " --evals 4000 --out " + dir.string());
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("on 3 MPI ranks x 1 thread"), std::string::npos) << o.output;
  std::size_t headers = 0;
  for (std::size_t at = o.output.find("qdmeta "); at != std::string::npos; at = o.output.find("qdmeta ", at + 1)) ++headers;
  EXPECT_EQ(headers, 1u) << "one rank speaks: " << o.output;
}

// SIGTERM to rank 0 alone (a user's kill, not the launcher's): the workers are alive and were
// never signalled, so none is named as crashed, and every one has exited when mpirun returns.
TEST(Mpi, ASignalToRankZeroAloneEndsTheRunAndEveryWorkerWithIt) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + config() + " --evals 60000 --seed 3 --out ";
  const fs::path straight = fresh_dir("straight-term"), stopped = fresh_dir("rank0-term");
  ASSERT_EQ(qdmeta_cli(run + straight.string() + " --quiet --threads 2").status, 0);
  // The hook reaches every rank; only rank 0 writes checkpoints, so only rank 0 signals itself.
  const Outcome o = mpirun(3, run + stopped.string(), "QDMETA_TEST_SIGNAL_AT_CHECKPOINT=1:TERM");
  EXPECT_EQ(o.status, 130) << o.output;  // interrupted, not a failed rank
  EXPECT_EQ(o.output.find("stopped answering"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("continue it with: qdmeta resume --out " + stopped.string()), std::string::npos) << o.output;
  EXPECT_FALSE(ranks_alive(stopped)) << "a worker outlived mpirun";
  ASSERT_TRUE(fs::exists(stopped / "checkpoint.bin")) << o.output;
  const Outcome r = qdmeta_cli("resume --quiet --out " + stopped.string() + " --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;
  expect_same_files(straight, stopped);
}

TEST(Mpi, AKilledWorkerStopsTheRunWithACheckpointThatResumesToTheSameBits) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + config() + " --evals 60000 --seed 3 --quiet --out ";
  const fs::path straight = fresh_dir("straight"), killed = fresh_dir("killed");
  ASSERT_EQ(qdmeta_cli(run + straight.string()).status, 0);
  // Rank 2 vanishes (SIGKILL) when its 31st piece arrives, a few generations in. The launcher's
  // default settings: OpenMPI signals the survivors 1 s (SIGTERM) and 2 s (SIGKILL) later.
  const Outcome o = mpirun(3, run + killed.string(), "QDMETA_TEST_KILL_RANK=2 QDMETA_TEST_KILL_AFTER=30");
  // OpenMPI's mpirun exits with the status of the first rank that failed: 128 + SIGKILL here,
  // whatever rank 0 returns (3) afterwards.
  EXPECT_EQ(o.status, 137) << o.output;
  EXPECT_NE(o.output.find("qdmeta: error: MPI rank 2 stopped answering (crashed or killed)"), std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("continue it with: qdmeta resume --out " + killed.string()), std::string::npos) << o.output;
  ASSERT_TRUE(fs::exists(killed / "checkpoint.bin")) << o.output;
  EXPECT_FALSE(fs::exists(killed / "summary.json")) << "a failed run must not look finished";
  EXPECT_FALSE(fs::exists(killed / "archive.csv")) << "a failed run must not look finished";
  // Continued without mpirun, on threads: the same bits as the run that never stopped.
  const Outcome r = qdmeta_cli("resume --out " + killed.string() + " --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("resuming from checkpoint"), std::string::npos) << r.output;
  expect_same_files(straight, killed);
  EXPECT_FALSE(fs::exists(killed / "checkpoint.bin"));
}

// A task whose own code throws on a worker rank ends the run as on threads (task_failure_test):
// one line naming the generation, the rank, the task and its batch row, and what was kept, with
// the exit status of a failed evaluation (4), not of a config error (2), which it had while a
// worker's report carried only its text.
TEST(Mpi, ATaskThatThrowsOnAWorkerIsAFailedEvaluation) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const fs::path dir = fresh_dir("throws-on-worker");
  const fs::path config = qdmeta::cli_test::faulty_task_config(
      "mpi_test", "throws-on-worker", "[task]\nname = \"throws\"\nthrow_after = 300\nthrow_on_rank = 1");
  const Outcome o = mpirun(2, "run --quiet --config " + config.string() + " --out " + dir.string(), "", QDMETA_FAULTY_BINARY);
  EXPECT_EQ(o.status, 4) << o.output;
  EXPECT_NE(o.output.find("qdmeta: error: evaluation failed in generation "), std::string::npos) << o.output;
  EXPECT_NE(o.output.find(" of the run: MPI rank 1: task 'throws' threw on row "), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("of the batch: simulator diverged"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(dir / "summary.json")) << "a failed run must not look finished";
}

TEST(Mpi, AKilledWorkerCanBeResumedUnderMpirunToo) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + config() + " --evals 40000 --seed 5 --quiet --out ";
  const fs::path straight = fresh_dir("straight2"), killed = fresh_dir("killed2");
  ASSERT_EQ(qdmeta_cli(run + straight.string() + " --threads 1").status, 0);
  const Outcome o = mpirun(2, run + killed.string(), "QDMETA_TEST_KILL_RANK=1 QDMETA_TEST_KILL_AFTER=12");
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("MPI rank 1 stopped answering"), std::string::npos) << o.output;
  ASSERT_TRUE(fs::exists(killed / "checkpoint.bin")) << o.output;
  const Outcome r = mpirun(3, "resume --quiet --out " + killed.string());
  ASSERT_EQ(r.status, 0) << r.output;
  expect_same_files(straight, killed);
}

// `mpirun` of `ranks` ranks started in the background; until `deadline` s, times (s from the
// start) when a rank first went missing after all had run, when dir/file appears, and then when
// no rank of the job is left; then the outcome. The tests compare these intervals with launcher
// timeouts many times longer than the work, so a slow or loaded machine passes them too.
struct Watched {
  Outcome outcome;
  double died = -1, appeared = -1, exited = -1;
};
Watched watch(const std::string& command, int ranks, const fs::path& dir, const char* file, double deadline) {
  Watched w;
  const auto start = Clock::now();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return w;
  bool all_ran = false;
  while (since(start) < deadline && w.exited < 0) {
    const int running = ranks_running(dir);
    all_ran = all_ran || running == ranks;
    if (all_ran && w.died < 0 && running < ranks) w.died = since(start);
    if (w.appeared < 0 && fs::exists(dir / file)) w.appeared = since(start);
    if (w.appeared >= 0 && running == 0) w.exited = since(start);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) w.outcome.output += buffer;
  const int raw = pclose(pipe);
  w.outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return w;
}

// With a long launcher timeout OpenMPI signals the survivors only T s after the death (and
// mpirun itself stays for about 2 T, its output held meanwhile): rank 0 must find the dead rank
// by itself, write the checkpoint at once, and every rank must exit without waiting for signals.
// Times are taken from the death, and T is far above the work's own time even on a loaded machine.
TEST(Mpi, RankZeroFindsADeadWorkerItselfUnderALongLauncherTimeout) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + config() + " --evals 60000 --seed 3 --quiet --out ";
  const fs::path straight = fresh_dir("straight3"), killed = fresh_dir("killed3");
  ASSERT_EQ(qdmeta_cli(run + straight.string()).status, 0);
  constexpr double kLauncherTimeout = 10;  // s: SIGTERM 10 s after the death, SIGKILL 10 s after that
  const Watched w = watch(mpirun_command(3, run + killed.string(),
                                         "OMPI_MCA_odls_base_sigkill_timeout=10 QDMETA_TEST_KILL_RANK=2 QDMETA_TEST_KILL_AFTER=30"),
                          3, killed, "checkpoint.bin", 100);
  const Outcome& o = w.outcome;
  ASSERT_GE(w.died, 0) << "no rank was seen to die\n" << o.output;
  ASSERT_GE(w.appeared, 0) << o.output;
  EXPECT_LT(w.appeared - w.died, kLauncherTimeout - 1) << "rank 0 waited for the launcher's SIGTERM\n" << o.output;
  EXPECT_GE(w.exited, 0) << "ranks still running";
  EXPECT_LT(w.exited - w.appeared, kLauncherTimeout / 2) << "the ranks waited for the launcher's signals";
  EXPECT_EQ(o.status, 137) << o.output;  // the dead rank's status, as with the default timeout
  EXPECT_NE(o.output.find("qdmeta: error: MPI rank 2 stopped answering (crashed or killed)"), std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("continue it with: qdmeta resume --out " + killed.string()), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(killed / "summary.json"));
  const Outcome r = qdmeta_cli("resume --out " + killed.string() + " --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;
  expect_same_files(straight, killed);
}

// A worker that dies after the last evaluation: the run is complete, and rank 0 must not wait in
// MPI_Finalize for it: it checks that every rank is there first, and warns.
TEST(Mpi, AWorkerDeadAtTheEndDoesNotHoldRankZeroInFinalize) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + config() + " --evals 20000 --seed 7 --quiet --out ";
  const fs::path straight = fresh_dir("straight5"), dir = fresh_dir("dead-at-end");
  ASSERT_EQ(qdmeta_cli(run + straight.string()).status, 0);
  // Were rank 0 to wait for the dead rank, only the launcher's signal, 10 s after the death, would end it.
  const Watched w = watch(mpirun_command(3, run + dir.string(),
                                         "OMPI_MCA_odls_base_sigkill_timeout=10 QDMETA_TEST_KILL_RANK=1 QDMETA_TEST_KILL_AFTER=stop"),
                          3, dir, "summary.json", 100);
  const Outcome& o = w.outcome;
  ASSERT_GE(w.appeared, 0) << o.output;
  EXPECT_GE(w.exited, 0) << "ranks still running";
  EXPECT_LT(w.exited - w.appeared, 5.0) << "rank 0 waited for the dead rank\n" << o.output;
  EXPECT_EQ(o.status, 137) << o.output;
  EXPECT_NE(o.output.find("qdmeta: warning: MPI rank 1 stopped answering (crashed or killed) after rank 0's last "
                          "evaluation"),
            std::string::npos)
      << o.output;
  expect_same_files(straight, dir);
}

// A rank that hangs (SIGSTOP: alive, silent) is found by its missing heartbeat
// (QDMETA_MPI_TIMEOUT); no rank died, so mpirun exits with the status 3 of the ranks.
TEST(Mpi, AHungWorkerIsFoundByItsMissingHeartbeat) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
  const std::string run = "run --config " + config() + " --evals 40000 --seed 5 --quiet --out ";
  const fs::path straight = fresh_dir("straight4"), hung = fresh_dir("hung");
  ASSERT_EQ(qdmeta_cli(run + straight.string() + " --threads 1").status, 0);
  const auto start = Clock::now();
  const Outcome o = mpirun(3, run + hung.string(),
                           "QDMETA_MPI_TIMEOUT=1 QDMETA_TEST_KILL_SIGNAL=STOP QDMETA_TEST_KILL_RANK=1 QDMETA_TEST_KILL_AFTER=12");
  EXPECT_EQ(o.status, 3) << o.output;
  EXPECT_LT(since(start), 60.0) << o.output;  // found by the 1 s heartbeat, not by the 120 s guard
  EXPECT_NE(o.output.find("qdmeta: error: MPI rank 1 stopped answering (crashed or killed)"), std::string::npos)
      << o.output;
  ASSERT_TRUE(fs::exists(hung / "checkpoint.bin")) << o.output;
  const Outcome r = mpirun(2, "resume --quiet --out " + hung.string());
  ASSERT_EQ(r.status, 0) << r.output;
  expect_same_files(straight, hung);
}

// The RHex QD-Meta smoke run: unshareable DART tasks, and a meta-fitness whose episodes over six
// damaged-leg environments go to the workers as one request (tasks named by index).
TEST(Mpi, RhexQdMetaGivesTheBitsOfAThreadRunOnThreeRanks) {
  if (const std::string why = unavailable(); !why.empty()) GTEST_SKIP() << why;
#ifndef QDMETA_TEST_RHEX
  GTEST_SKIP() << "qdmeta was built without the RHex task (DART)";
#endif
  // The initial population and one meta-generation: about 300 one-second episodes a run.
  const std::string run = "run --config " + std::string(QDMETA_SOURCE_DIR) +
                          "/configs/rhex/smoke-damage.toml --evals 100 --quiet --out ";
  const fs::path threads = fresh_dir("rhex-threads");
  ASSERT_EQ(qdmeta_cli(run + threads.string() + " --threads 2").status, 0);
  ASSERT_NE(slurp(threads / "meta.csv").find('\n'), std::string::npos);
  for (int ranks : {3}) {
    const fs::path dir = fresh_dir("rhex-ranks" + std::to_string(ranks));
    const Outcome o = mpirun(ranks, run + dir.string());
    ASSERT_EQ(o.status, 0) << o.output;
    expect_same_files(threads, dir);
    EXPECT_EQ(slurp(threads / "meta.csv"), slurp(dir / "meta.csv")) << "meta.csv, " << ranks << " ranks";
  }
}

}  // namespace
