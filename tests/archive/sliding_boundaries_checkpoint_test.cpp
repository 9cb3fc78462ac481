// SlidingBoundariesArchive's checkpoints (save/load): a loaded archive continues, through the
// remaps after the checkpoint, to the same bits as the original; other dims are refused.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/archive/sliding_boundaries_archive.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

SlidingBoundariesParams grid(std::vector<Index> dims) {
  SlidingBoundariesParams p;
  p.solution_size = 2;
  p.dims = std::move(dims);
  p.lower_bounds.assign(p.dims.size(), 0.0);
  p.upper_bounds.assign(p.dims.size(), 1.0);
  p.remap_frequency = 7;
  p.buffer_capacity = 30;
  return p;
}

// `rows` uniform points of two measures; solution = measures, objective = their sum.
void add_rows(SlidingBoundariesArchive& a, Rng& rng, int rows) {
  std::vector<double> x, f;
  for (int r = 0; r < rows; ++r) {
    const double u = rng.uniform(), v = rng.uniform();
    x.insert(x.end(), {u, v});
    f.push_back(u + v);
  }
  a.add(x, f, x);
}

std::string saved(const SlidingBoundariesArchive& a) {
  BinaryWriter out;
  a.save(out);
  return out.bytes();
}

TEST(SlidingBoundariesCheckpoint, ALoadedArchiveContinuesThroughRemapsToTheSameBits) {
  SlidingBoundariesArchive a(grid({5, 4}));
  Rng rng(3);
  add_rows(a, rng, 45);  // six remaps and three rows since the last; the buffer is full
  SlidingBoundariesArchive b(grid({5, 4}));
  const std::string checkpoint = saved(a);  // the reader views it
  BinaryReader in(checkpoint, "test");
  b.load(in);
  in.finish();
  EXPECT_EQ(saved(b), checkpoint);
  const std::vector<double> before = a.boundaries(0);
  Rng again = rng;
  add_rows(a, rng, 40);
  add_rows(b, again, 40);
  EXPECT_EQ(saved(b), saved(a));
  EXPECT_NE(a.boundaries(0), before);  // it remapped after the checkpoint
}

TEST(SlidingBoundariesCheckpoint, RefusesAnArchiveOfOtherDims) {
  SlidingBoundariesArchive a(grid({5, 4}));
  SlidingBoundariesArchive b(grid({4, 5}));
  const std::string checkpoint = saved(a);
  BinaryReader in(checkpoint, "test");
  const std::string message = input_error_message([&] { b.load(in); });
  EXPECT_NE(message.find("has 2 genes and dims [5, 4]; this one 2 and [4, 5]"), std::string::npos) << message;
}

}  // namespace
}  // namespace qdmeta
