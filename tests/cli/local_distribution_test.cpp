// A program built without qdmeta::mpi that an MPI launcher starts several times: every rank stops
// at once with a config error's status, rank 0 saying what to link, instead of each rank running
// the whole command into the same directory (what a test's own faulty-task binary did, unnoticed,
// before it linked qdmeta::mpi).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <string>

#include "qdmeta/cli/distribution.hpp"
#include "qdmeta/cli/distribution_factory.hpp"

namespace qdmeta {
namespace {

// Sets the launcher's variables for one test, and removes them after.
struct LauncherEnv {
  LauncherEnv(const char* size, const char* rank) {
    ::setenv("OMPI_COMM_WORLD_SIZE", size, 1);
    ::setenv("OMPI_COMM_WORLD_RANK", rank, 1);
  }
  ~LauncherEnv() {
    ::unsetenv("OMPI_COMM_WORLD_SIZE");
    ::unsetenv("OMPI_COMM_WORLD_RANK");
  }
};

std::optional<int> serve(std::string& printed) {
  int argc = 1;
  char name[] = "program";
  char* args[] = {name, nullptr};
  char** argv = args;
  testing::internal::CaptureStderr();
  const auto status = make_local_distribution(argc, argv)->serve_if_worker();
  printed = testing::internal::GetCapturedStderr();
  return status;
}

TEST(LocalDistribution, WithoutALauncherTheProgramRuns) {
  std::string printed;
  EXPECT_EQ(serve(printed), std::nullopt);
  EXPECT_EQ(printed, "");
  const LauncherEnv one("1", "0");  // mpirun -np 1: one process, nothing to share
  EXPECT_EQ(serve(printed), std::nullopt);
}

TEST(LocalDistribution, SeveralRanksWithoutMpiAllStopAndRankZeroSaysWhy) {
  std::string printed;
  {
    const LauncherEnv rank0("3", "0");
    EXPECT_EQ(serve(printed), 2);
    EXPECT_EQ(printed,
              "qdmeta: error: started by an MPI launcher as 3 ranks, but this program was built without MPI (it does "
              "not link qdmeta::mpi): each rank would run the whole command into the same directory. Link qdmeta::mpi "
              "(find_package(qdmeta COMPONENTS mpi)), or run it without the launcher (--threads N)\n");
  }
  const LauncherEnv rank2("3", "2");
  EXPECT_EQ(serve(printed), 2);
  EXPECT_EQ(printed, "") << "one message, from rank 0";
}

}  // namespace
}  // namespace qdmeta
