#pragma once
// Files that are either whole or absent: written to a temporary file of their own beside the
// target ("<path>.tmp-<pid>-<n>", created exclusively: never through a planted link, never
// shared by two writers), then renamed over <path> (which replaces a link there, not its target).
#include <filesystem>
#include <string_view>

namespace qdmeta {

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();  // removes the temporary file unless commit() succeeded
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Appends to the temporary file; Error on any I/O failure.
  void write(std::string_view bytes);
  // Closes and renames; throws Error on any I/O failure.
  void commit();
  const std::filesystem::path& temporary_path() const { return tmp_; }

 private:
  std::filesystem::path path_;
  std::filesystem::path tmp_;
  int fd_ = -1;
  bool committed_ = false;
};

void write_file_atomic(const std::filesystem::path& path, std::string_view content);

}  // namespace qdmeta
