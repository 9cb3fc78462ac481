#pragma once
// The machine's side of a run's memory estimate (core/memory_estimate.hpp): what this process
// may use, and the check that refuses a config whose estimate exceeds it.
#include <optional>
#include <string>

#include "qdmeta/core/memory_estimate.hpp"

namespace qdmeta {

// What this process may use: the least of physical memory, the address-space limit (ulimit -v)
// and the cgroup's memory.max; nullopt when none can be read.
struct MemoryLimit {
  double bytes = 0;
  std::string source;  // "physical memory", "ulimit -v", "cgroup memory.max"
};
std::optional<MemoryLimit> memory_limit();

// "1.50 GiB", "812 MiB", "64.0 KiB".
std::string format_bytes(double bytes);

// Throws InputError (naming `source`, the total, the largest terms with their keys and the limit)
// when the estimate exceeds `limit`.
void require_memory(const MemoryEstimate& estimate, const std::optional<MemoryLimit>& limit, const std::string& source);

}  // namespace qdmeta
