// Another program's stderr captured: its text and status come back, a flood past the limit
// neither blocks the program nor grows without bound.
#include "qdmeta/io/subprocess.hpp"

#include <gtest/gtest.h>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

TEST(Subprocess, StderrAndStatusComeBack) {
  const ProgramOutcome r = run_program_capturing_stderr({"/bin/sh", "-c", "echo one >&2; echo two >&2; exit 2"}, 1000);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.error_output, "one\ntwo\n");
  EXPECT_EQ(run_program_capturing_stderr({"/bin/sh", "-c", "kill -TERM $$"}, 1000).status, 128 + 15);
}

TEST(Subprocess, AFloodIsCutAtTheLimitWithoutBlockingTheProgram) {
  // 4 MB: far past a pipe's buffer, so the program would block if nobody read the rest.
  const ProgramOutcome r =
      run_program_capturing_stderr({"/bin/sh", "-c", "head -c 4000000 /dev/zero | tr '\\0' x >&2; exit 3"}, 100);
  EXPECT_EQ(r.status, 3);
  EXPECT_EQ(r.error_output, std::string(100, 'x'));
}

TEST(Subprocess, AProgramThatCannotStartIsAnError) {
  EXPECT_THROW(run_program_capturing_stderr({"/no/such/program"}, 100), Error);
}

}  // namespace
}  // namespace qdmeta
