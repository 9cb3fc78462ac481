#include "qdmeta/io/atomic_file.hpp"

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/std.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"

namespace qdmeta {

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)) {
  fd_ = create_temporary_beside(path_, tmp_);
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
  }
}

void AtomicFile::write(std::string_view bytes) { write_all(fd_, bytes, tmp_); }

void AtomicFile::commit() {
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) throw Error(fmt::format("writing {} failed: {}", tmp_, std::strerror(errno)));
  std::error_code ec;
  std::filesystem::rename(tmp_, path_, ec);
  if (ec) throw Error(fmt::format("cannot rename {} to {}: {}", tmp_, path_, ec.message()));
  committed_ = true;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  AtomicFile file(path);
  file.write(content);
  file.commit();
}

}  // namespace qdmeta
