#pragma once
// Starting another program (the report script) from an argument vector: no shell ever sees the
// arguments, so a path holding quotes, spaces, `$()`, `;`, backticks or newlines is passed to the
// program exactly as it is and can never be interpreted as a command.
#include <cstddef>
#include <string>
#include <vector>

namespace qdmeta {

// Runs argv[0] (looked up on PATH when it holds no '/') with argv, inheriting stdin, stdout and
// stderr, and waits for it. Returns its exit status; a program killed by a signal gives 128 +
// the signal number, as a shell reports it. Throws Error when it cannot be started at all.
int run_program(const std::vector<std::string>& argv);

struct ProgramOutcome {
  int status = 0;            // as run_program's
  std::string error_output;  // what it wrote to stderr, at most the limit's bytes
};

// As run_program, but the program's stderr comes back instead of reaching ours, so the caller
// decides what the user sees. Past `limit` bytes the rest is read and dropped: the program never
// blocks on a full pipe.
ProgramOutcome run_program_capturing_stderr(const std::vector<std::string>& argv, std::size_t limit);

}  // namespace qdmeta
