#pragma once
// The library's one parallel loop: body(0) ... body(n - 1) on oneTBB, one index per task. Each
// index owns its outputs (and its random stream), so the result does not depend on how the
// indices are split over threads. Inside Evaluator::within_workers it runs on that evaluator's
// threads only (the thread evaluator's parallel_for is this loop in its arena).
#include <functional>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

void parallel_indices(Index n, const std::function<void(Index)>& body);

// parallel_indices whose error is the one a loop in index order would throw: every index runs,
// then the exception of the lowest index that threw is rethrown (the same message at any thread
// count, where oneTBB would rethrow whichever came first).
void parallel_indices_lowest_error(Index n, const std::function<void(Index)>& body);

}  // namespace qdmeta
