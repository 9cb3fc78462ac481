#pragma once
// key=value arguments of the RHex comparison programs (rhex_engines, rhex_turning): each key must
// be one of the defaults'; a bad one is reported on one line, naming the valid keys.
#include <fmt/format.h>

#include <map>
#include <string>

namespace qdmeta::bench {

// Fills `args` (holding the defaults) from argv; false (after printing why) on a bad argument.
inline bool read_key_values(int argc, char** argv, const char* program, std::map<std::string, std::string>& args) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    if (eq == std::string::npos || !args.contains(a.substr(0, eq))) {
      std::string keys;
      for (const auto& [k, v] : args) keys += (keys.empty() ? "" : " ") + k;
      fmt::print(stderr, "{}: bad argument '{}' (key=value, keys: {})\n", program, a, keys);
      return false;
    }
    args[a.substr(0, eq)] = a.substr(eq + 1);
  }
  return true;
}

}  // namespace qdmeta::bench
