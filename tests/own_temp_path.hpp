#pragma once
// A path under TMPDIR that is this test process's own. ctest runs tests as parallel processes and
// two suites (Release and sanitizers) may run at once, so a fixed name such as
// /tmp/qdmeta_table_test would be written by two of them together.
#include <unistd.h>

#include <filesystem>
#include <string>

namespace qdmeta::test {

// TMPDIR/qdmeta_<pid>_<name>; nothing is made there.
inline std::filesystem::path own_temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("qdmeta_" + std::to_string(::getpid()) + "_" + name);
}

}  // namespace qdmeta::test
