#include "qdmeta/core/huge_pages.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <vector>

namespace qdmeta {
namespace {

// The hint must never change memory: a range holding no whole huge page, a null pointer and a
// large buffer (advised before and after it is written) all keep their contents.
TEST(HugePages, AdviceIsOnlyAHint) {
  advise_huge_pages(nullptr, 1 << 22);
  std::vector<std::uint32_t> small(100, 7);
  advise_huge_pages(small.data(), small.size() * sizeof(std::uint32_t));
  for (std::uint32_t x : small) ASSERT_EQ(x, 7u);

  const std::size_t count = std::size_t{6} << 20;  // 24 MB: several whole 2 MiB pages inside
  auto* big = static_cast<std::uint32_t*>(std::malloc(count * sizeof(std::uint32_t)));
  ASSERT_NE(big, nullptr);
  advise_huge_pages(big, count * sizeof(std::uint32_t));
  for (std::size_t i = 0; i < count; ++i) big[i] = static_cast<std::uint32_t>(i * 2654435761u);
  advise_huge_pages(big + 3, (count - 3) * sizeof(std::uint32_t));
  for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(big[i], static_cast<std::uint32_t>(i * 2654435761u)) << i;
  std::free(big);
}

}  // namespace
}  // namespace qdmeta
