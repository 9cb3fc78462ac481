#include "qdmeta/io/subprocess.hpp"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>

#include "qdmeta/core/error.hpp"

extern char** environ;

namespace qdmeta {

int run_program(const std::vector<std::string>& argv) {
  if (argv.empty()) throw Error("run_program: no program given");
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  // posix_spawnp, not fork + exec: safe in a process with threads (TBB, MPI).
  const int started = posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ);
  if (started != 0) throw Error(fmt::format("cannot start {}: {}", argv[0], std::strerror(started)));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error(fmt::format("waiting for {}: {}", argv[0], std::strerror(errno)));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

}  // namespace qdmeta
