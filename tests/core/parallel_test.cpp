// Tests of src/qdmeta/core/parallel.{hpp,cpp}: the one parallel loop visits every index exactly
// once, however many indices and threads.
#include "qdmeta/core/parallel.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <vector>

namespace qdmeta {
namespace {

TEST(ParallelIndices, EveryIndexExactlyOnce) {
  for (const int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    for (const Index n : {Index{0}, Index{1}, Index{2}, Index{7}, Index{1000}}) {
      std::vector<std::atomic<int>> visits(static_cast<std::size_t>(n));
      arena.execute([&] { parallel_indices(n, [&](Index i) { visits[static_cast<std::size_t>(i)].fetch_add(1); }); });
      for (Index i = 0; i < n; ++i)
        EXPECT_EQ(visits[static_cast<std::size_t>(i)].load(), 1) << "index " << i << " of " << n << ", " << threads
                                                                  << " threads";
    }
  }
}

}  // namespace
}  // namespace qdmeta
