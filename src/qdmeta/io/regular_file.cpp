#include "qdmeta/io/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>
#include <fmt/std.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <utility>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Closes a descriptor on every path out of a function.
struct FdGuard {
  int fd;
  ~FdGuard() {
    if (fd >= 0) ::close(fd);
  }
  int release() { return std::exchange(fd, -1); }
};

std::uint64_t checked_size(int fd, const std::filesystem::path& path, std::uint64_t max_bytes) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw InputError(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
  if (!S_ISREG(st.st_mode))
    throw InputError(fmt::format("{} is {}, not a regular file: it was replaced or damaged", path, kind_of(st.st_mode)));
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes)
    throw InputError(fmt::format("{} holds {} bytes, more than the {} such a file may: it is not one qdmeta wrote", path,
                                 size, max_bytes));
  return size;
}

// O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer before fstat could
// refuse it. It changes nothing for a regular file.
int open_for_reading(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    if (errno == ENOENT) throw InputError(fmt::format("{} does not exist", path));
    throw InputError(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
  }
  return fd;
}

}  // namespace

std::uint64_t regular_file_size(const std::filesystem::path& path, std::uint64_t max_bytes) {
  FdGuard fd{open_for_reading(path)};
  return checked_size(fd.fd, path, max_bytes);
}

std::string read_regular_file(const std::filesystem::path& path, std::uint64_t max_bytes) {
  FdGuard fd{open_for_reading(path)};
  const std::uint64_t size = checked_size(fd.fd, path, max_bytes);
  // To the end of the file, not to its stated size: files under /proc say 0 bytes and hold more.
  // One byte more than stated, so a file of its stated size ends without the buffer growing.
  std::string bytes(static_cast<std::size_t>(std::min(std::max<std::uint64_t>(size + 1, 4096), max_bytes + 1)), '\0');
  std::size_t done = 0;
  for (;;) {
    if (done == bytes.size()) {
      if (done > max_bytes) break;  // past the bound: refused below
      bytes.resize(static_cast<std::size_t>(std::min<std::uint64_t>(2 * bytes.size(), max_bytes + 1)));
    }
    const ssize_t n = ::read(fd.fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  if (done > max_bytes)
    throw InputError(fmt::format("{} holds more than the {} bytes such a file may: it is not one qdmeta wrote", path,
                                 max_bytes));
  bytes.resize(done);
  return bytes;
}

bool path_taken(const std::filesystem::path& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0;
}

int create_file_replacing(const std::filesystem::path& path) {
  if (::unlink(path.c_str()) != 0 && errno != ENOENT)
    throw Error(fmt::format("cannot replace {}: {}", path, std::strerror(errno)));
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) throw Error(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  return fd;
}

namespace {
[[noreturn]] void throw_symbolic_link(const std::filesystem::path& path) {
  throw InputError(fmt::format("{} is a symbolic link: qdmeta writes only its own files", path));
}
}  // namespace

void refuse_symbolic_link(const std::filesystem::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) throw_symbolic_link(path);
}

int open_file_for_append(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    if (errno == ELOOP) throw_symbolic_link(path);
    throw Error(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  }
  FdGuard guard{fd};
  checked_size(fd, path, kMaxTableFileBytes);
  if (::fcntl(fd, F_SETFL, O_APPEND) != 0) throw Error(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  return guard.release();
}

int create_temporary_beside(const std::filesystem::path& path, std::filesystem::path& tmp_path) {
  // A name of this process and call (two writers never share one), created with O_EXCL: nothing,
  // a planted link included, can stand there already. Mode 0666 less the umask, as any new file.
  static std::atomic<std::uint64_t> calls{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    tmp_path = path;
    tmp_path += fmt::format(".tmp-{}-{}", ::getpid(), calls.fetch_add(1));
    const int fd = ::open(tmp_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
    if (errno != EEXIST) break;  // a leftover of a dead process with our pid: try the next name
  }
  throw Error(fmt::format("cannot write {}: {}", tmp_path, std::strerror(errno)));
}

bool is_temporary_name(std::string_view filename) {
  const auto digits = [](std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  const std::size_t tmp = filename.rfind(".tmp-");
  if (tmp == std::string_view::npos || tmp == 0) return false;
  const std::string_view rest = filename.substr(tmp + 5);
  const std::size_t dash = rest.find('-');
  return dash != std::string_view::npos && digits(rest.substr(0, dash)) && digits(rest.substr(dash + 1));
}

int remove_dead_temporaries(const std::filesystem::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::filesystem::path& p = it->path();
    if (is_temporary_name(p.filename().string()) && it->is_regular_file(ec) && std::filesystem::remove(p, ec)) ++removed;
  }
  return removed;
}

void write_all(int fd, std::string_view bytes, const std::filesystem::path& path) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EFBIG)
      throw Error(fmt::format("writing {} failed: {}: the file size limit (ulimit -f) was reached", path,
                              std::strerror(EFBIG)));
    if (n <= 0) throw Error(fmt::format("writing {} failed: {}", path, std::strerror(n < 0 ? errno : EIO)));
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

}  // namespace qdmeta
