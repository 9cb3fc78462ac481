#include "qdmeta/io/subprocess.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "qdmeta/core/error.hpp"

extern char** environ;

namespace qdmeta {

namespace {

// posix_spawnp, not fork + exec: safe in a process with threads (TBB, MPI).
pid_t spawn(const std::vector<std::string>& argv, const posix_spawn_file_actions_t* actions) {
  if (argv.empty()) throw Error("run_program: no program given");
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int started = posix_spawnp(&pid, args[0], actions, nullptr, args.data(), environ);
  if (started != 0) throw Error(fmt::format("cannot start {}: {}", argv[0], std::strerror(started)));
  return pid;
}

int wait_for(pid_t pid, const std::string& name) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error(fmt::format("waiting for {}: {}", name, std::strerror(errno)));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

// Closes a descriptor when it goes out of scope, unless it was closed already (-1).
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) close(fd);
  }
  void close_now() {
    close(fd);
    fd = -1;
  }
};

}  // namespace

int run_program(const std::vector<std::string>& argv) { return wait_for(spawn(argv, nullptr), argv.at(0)); }

ProgramOutcome run_program_capturing_stderr(const std::vector<std::string>& argv, std::size_t limit) {
  int ends[2];
  // Close-on-exec: only the dup2 below reaches the program, as its stderr.
  if (pipe2(ends, O_CLOEXEC) != 0) throw Error(fmt::format("cannot make a pipe: {}", std::strerror(errno)));
  Fd read_end{ends[0]}, write_end{ends[1]};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, write_end.fd, STDERR_FILENO);
  pid_t pid = 0;
  try {
    pid = spawn(argv, &actions);
  } catch (...) {
    posix_spawn_file_actions_destroy(&actions);
    throw;
  }
  posix_spawn_file_actions_destroy(&actions);
  write_end.close_now();  // so that the read ends when the program (and its children) close theirs
  ProgramOutcome out;
  char buffer[4096];
  for (;;) {
    const ssize_t n = read(read_end.fd, buffer, sizeof buffer);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      break;  // the status still tells how it ended
    }
    const std::size_t room = limit - std::min(limit, out.error_output.size());
    out.error_output.append(buffer, std::min(room, static_cast<std::size_t>(n)));
  }
  read_end.close_now();  // after a read error, a program still writing gets EPIPE rather than blocking
  out.status = wait_for(pid, argv.at(0));
  return out;
}

}  // namespace qdmeta
