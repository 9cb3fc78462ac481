#pragma once
// Wall-clock seconds since a steady_clock time point: the one timer of timing decisions (the
// thread evaluator's cheap-batch rule, a failed task's row search) and progress lines.
#include <chrono>

namespace qdmeta {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace qdmeta
