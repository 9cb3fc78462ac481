#pragma once
// Starting another program (the report script) from an argument vector: no shell ever sees the
// arguments, so a path holding quotes, spaces, `$()`, `;`, backticks or newlines is passed to the
// program exactly as it is and can never be interpreted as a command.
#include <string>
#include <vector>

namespace qdmeta {

// Runs argv[0] (looked up on PATH when it holds no '/') with argv, inheriting stdin, stdout and
// stderr, and waits for it. Returns its exit status; a program killed by a signal gives 128 +
// the signal number, as a shell reports it. Throws Error when it cannot be started at all.
int run_program(const std::vector<std::string>& argv);

}  // namespace qdmeta
