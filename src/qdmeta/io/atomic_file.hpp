#pragma once
// Files that are either whole or absent: written to "<path>.tmp", then renamed over <path>.
#include <filesystem>
#include <fstream>
#include <string_view>

namespace qdmeta {

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();  // removes the temporary file unless commit() succeeded
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  std::ofstream& stream() { return out_; }
  // Flushes, closes and renames; throws Error on any I/O failure.
  void commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

void write_file_atomic(const std::filesystem::path& path, std::string_view content);

}  // namespace qdmeta
