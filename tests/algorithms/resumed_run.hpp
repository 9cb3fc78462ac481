#pragma once
// A run checkpointed between steps and continued in an algorithm built afresh: `before` steps of
// make(), save(), load() into another make(), `after` more steps. The caller compares the result
// with make() stepped before + after times straight.
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/evaluator.hpp"

namespace qdmeta {

template <class Make>
auto resumed_run(Make make, int before, int after, Evaluator& evaluator) {
  auto first = make();
  for (int t = 0; t < before; ++t) first.step(evaluator);
  BinaryWriter out;
  first.save(out);
  auto second = make();
  BinaryReader in(out.bytes(), "memory");
  second.load(in);
  in.finish();
  for (int t = 0; t < after; ++t) second.step(evaluator);
  return second;
}

}  // namespace qdmeta
