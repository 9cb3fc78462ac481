#include "qdmeta/archive/list_selection.hpp"

#include <algorithm>
#include <array>

namespace qdmeta {

std::uint64_t select_smallest(const std::vector<std::uint64_t>& keys, Index count, std::vector<std::uint64_t>& chosen,
                              std::vector<std::uint64_t>& scratch) {
  // Value buckets of equal width between the smallest and largest value: (v - lo) * scale is
  // monotone in v, so every key of a lower bucket is smaller than every key of a higher one.
  // The bucket where the count is reached is the only one that needs a selection of its own.
  constexpr int kBuckets = 64;
  Real lo = key_value(keys.front()), hi = lo;
  for (std::uint64_t key : keys) {
    lo = std::min(lo, key_value(key));
    hi = std::max(hi, key_value(key));
  }
  const double width = static_cast<double>(hi) - static_cast<double>(lo);
  const double scale = width > 0 ? kBuckets / width : 0.0;
  thread_local std::vector<std::uint8_t> buckets;
  buckets.resize(keys.size());
  std::array<Index, kBuckets> sizes{};
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const double t = (static_cast<double>(key_value(keys[i])) - static_cast<double>(lo)) * scale;
    const auto b = static_cast<std::uint8_t>(std::min(kBuckets - 1, static_cast<int>(t)));
    buckets[i] = b;
    ++sizes[b];
  }
  int edge = 0;
  Index below = 0;  // keys in buckets before `edge`
  while (below + sizes[static_cast<std::size_t>(edge)] <= count) below += sizes[static_cast<std::size_t>(edge++)];
  // The edge bucket has more keys than the `count - below` still wanted: the smallest of them
  // go in, and the next one is the smallest key left out of the whole set.
  // Branch-free compactions: which keys go where is data, not control flow.
  scratch.resize(keys.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    scratch[n] = keys[i];
    n += buckets[i] == edge;
  }
  scratch.resize(n);
  const auto wanted = static_cast<std::size_t>(count - below);
  std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(wanted), scratch.end());
  const std::uint64_t next = scratch[wanted];
  chosen.resize(keys.size());
  n = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    chosen[n] = keys[i];
    n += (buckets[i] < edge) | ((buckets[i] == edge) & (keys[i] < next));
  }
  chosen.resize(n);
  return next;
}

void sort_by_value(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch) {
  // Least significant digit first over the value's 32 bits, 8 at a time; a digit all keys
  // share is skipped.
  scratch.resize(keys.size());
  for (int shift = 32; shift < 64; shift += 8) {
    std::array<std::size_t, 257> start{};
    for (std::uint64_t key : keys) ++start[((key >> shift) & 0xff) + 1];
    if (std::any_of(start.begin() + 1, start.end(), [&](std::size_t n) { return n == keys.size(); })) continue;
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    for (std::uint64_t key : keys) scratch[start[(key >> shift) & 0xff]++] = key;
    keys.swap(scratch);
  }
}

}  // namespace qdmeta
