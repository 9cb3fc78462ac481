#pragma once
// A run's memory, estimated from its config before anything is allocated, so that a config that
// cannot fit stops with a message naming the keys that make it large instead of a bare
// std::bad_alloc minutes into the run (or a machine driven into swap).
//
// The estimate counts the large blocks each algorithm allocates (archives, database, offspring
// buffers, CMA-ES matrices, k-means points, autoencoder): a lower bound, good to a small factor.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace qdmeta {

struct MemoryTerm {
  std::string what;  // e.g. "the circular database"
  std::string keys;  // the config keys and sizes it grows with, e.g. "qd_meta.database_capacity x (genes + base features)"
  double bytes = 0;
};

struct MemoryEstimate {
  std::vector<MemoryTerm> terms;
  void add(std::string what, std::string keys, double bytes) { terms.push_back({std::move(what), std::move(keys), bytes}); }
  double total() const;
};

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
