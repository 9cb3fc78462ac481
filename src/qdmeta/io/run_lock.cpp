#include "qdmeta/io/run_lock.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"

namespace qdmeta {

void require_room_for_run_files(const std::filesystem::path& dir) {
  const std::size_t length = dir.native().size();
  if (length + 1 + kRunFileNameRoom >= PATH_MAX)
    throw InputError(fmt::format("{} is too long a path for a run ({} bytes): the files written in it would pass the "
                                 "system's limit of {} bytes; use a shorter one",
                                 dir.string(), length, PATH_MAX));
}

RunLock::RunLock(const std::filesystem::path& dir, Mode mode, Missing missing) {
  std::error_code ec;
  if (missing == Missing::kCreate) {
    require_room_for_run_files(dir);
    std::filesystem::create_directories(dir, ec);
    if (ec) throw InputError(fmt::format("cannot create {}: {}", dir.string(), ec.message()));
  } else if (!std::filesystem::is_directory(dir, ec)) {
    throw InputError(fmt::format("{} is not a directory: no run there", dir.string()));
  }
  // O_CLOEXEC: a child (the report script) must not inherit, and so prolong, the lock.
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw InputError(fmt::format("cannot open {}: {}", dir.string(), std::strerror(errno)));
  const int how = (mode == Mode::kExclusive ? LOCK_EX : LOCK_SH) | LOCK_NB;
  int rc = 0;
  while ((rc = ::flock(fd_, how)) != 0 && errno == EINTR) {
  }
  if (rc != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK)
      throw InputError(fmt::format("{} is in use by another qdmeta process (a run, resume, experiment or test phase "
                                   "writing to it): wait for it to end, or use another directory",
                                   dir.string()));
    throw InputError(fmt::format("cannot lock {}: {}", dir.string(), std::strerror(error)));
  }
  if (mode == Mode::kExclusive) remove_dead_temporaries(dir);  // the lock says their writer is gone
}

RunLock::~RunLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the lock
}

RunLock::RunLock(RunLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

}  // namespace qdmeta
