#pragma once
// A run's memory, estimated before anything is allocated: each algorithm and archive adds the
// large blocks it will allocate (next to the code that allocates them), and the run's builder
// checks the total against the machine (assembly/memory_estimate.hpp), so that a config that
// cannot fit stops with a message naming the keys that make it large instead of a bare
// std::bad_alloc minutes into the run. A lower bound, good to a small factor.
#include <string>
#include <utility>
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
  double total() const {
    double sum = 0;
    for (const MemoryTerm& t : terms) sum += t.bytes;
    return sum;
  }
};

}  // namespace qdmeta
