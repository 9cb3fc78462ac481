#pragma once
// Selection and sorting for neighbour lists without comparison sorts (whose mispredicted
// branches cost more than the arithmetic): keys that order as (float value, index), the
// `count` smallest of them by value buckets, and a stable radix sort.
#include <cstdint>
#include <cstring>
#include <vector>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

// A key that sorts as (value, index): the float's bits made monotone (negative values flipped
// whole, the others with the sign bit set) above the index.
inline std::uint64_t value_key(Real value, Index index) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  bits = (bits >> 31) != 0 ? ~bits : bits | 0x80000000u;
  return (static_cast<std::uint64_t>(bits) << 32) | static_cast<std::uint32_t>(index);
}
inline Real key_value(std::uint64_t key) {
  auto bits = static_cast<std::uint32_t>(key >> 32);
  bits = (bits >> 31) != 0 ? bits & 0x7fffffffu : ~bits;
  Real value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
inline std::int32_t key_index(std::uint64_t key) { return static_cast<std::int32_t>(key & 0xffffffffu); }

// The `count` smallest of `keys` (0 < count < keys.size(), values finite) into `chosen`, in
// the order they have in `keys`; returns the smallest key left out. `scratch` is reused.
std::uint64_t select_smallest(const std::vector<std::uint64_t>& keys, Index count, std::vector<std::uint64_t>& chosen,
                              std::vector<std::uint64_t>& scratch);

// Sorts `keys` by value, stably (keys in index order end up sorted as (value, index)).
void sort_by_value(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch);

}  // namespace qdmeta
