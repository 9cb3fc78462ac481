#include "qdmeta/core/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <exception>
#include <vector>

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

void parallel_indices_lowest_error(Index n, const std::function<void(Index)>& body) {
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  parallel_indices(n, [&](Index i) {
    try {
      body(i);
    } catch (...) {
      errors[static_cast<std::size_t>(i)] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

}  // namespace qdmeta
