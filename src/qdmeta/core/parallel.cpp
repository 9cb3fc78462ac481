#include "qdmeta/core/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

namespace qdmeta {

void parallel_indices(Index n, const std::function<void(Index)>& body) {
  // Grain 1 with the simple partitioner: one index per task, however few indices there are.
  tbb::parallel_for(
      tbb::blocked_range<Index>(0, n, 1),
      [&](const tbb::blocked_range<Index>& range) {
        for (Index i = range.begin(); i < range.end(); ++i) body(i);
      },
      tbb::simple_partitioner());
}

}  // namespace qdmeta
