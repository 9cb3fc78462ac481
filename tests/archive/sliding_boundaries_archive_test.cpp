// The sliding-boundaries archive on a remap worked by hand (the Python suite also holds it to
// pyribs's SlidingBoundariesArchive through many remaps with a rolling buffer).
#include "qdmeta/archive/sliding_boundaries_archive.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

SlidingBoundariesParams two_cells() {
  SlidingBoundariesParams p;
  p.solution_size = 1;
  p.dims = {2};
  p.lower_bounds = {0.0};
  p.upper_bounds = {1.0};
  p.epsilon = 0.0;
  p.remap_frequency = 4;
  p.buffer_capacity = 4;
  return p;
}

TEST(SlidingBoundariesArchive, RemapsToTheBuffersQuantilesAndAddsEverythingAgain) {
  SlidingBoundariesArchive a(two_cells());
  EXPECT_EQ(a.boundaries(0), (std::vector<double>{0.0, 0.5, 1.0}));
  const std::vector<double> at{0.1, 0.2, 0.3};
  const auto first = a.add(at, std::vector<double>{1.0, 2.0, 3.0}, at);
  EXPECT_EQ(first.status, (std::vector<std::uint8_t>{2, 1, 1}));  // all in [0, 0.5)
  EXPECT_EQ(first.value, (std::vector<double>{1.0, 1.0, 1.0}));
  // The fourth solution remaps: sorted buffer 0.1 0.2 0.3 0.9 -> boundaries at ranks 0 and 2,
  // and the largest: 0.1, 0.3, 0.9. Re-added: the elite (0.3, f 3), then 0.1, 0.2, 0.3 (none
  // beats it: 0.3 sits on a boundary and, with epsilon 0, in the cell below), then 0.9, new.
  const auto fourth = a.add(std::vector<double>{0.9}, std::vector<double>{4.0}, std::vector<double>{0.9});
  EXPECT_EQ(fourth.status, (std::vector<std::uint8_t>{2}));
  EXPECT_EQ(fourth.value, (std::vector<double>{4.0}));
  EXPECT_EQ(a.boundaries(0), (std::vector<double>{0.1, 0.3, 0.9}));
  EXPECT_EQ(a.elite_cells(), (std::vector<Index>{0, 1}));
  EXPECT_EQ(a.objective(0), 3.0);
  EXPECT_EQ(a.measures(1)[0], 0.9);
  EXPECT_EQ(a.stats().qd_score, 7.0);
  EXPECT_EQ(a.stats().coverage, 1.0);
}

TEST(SlidingBoundariesArchive, CellsAreRowMajorOverTheEvenGridBeforeAnyRemap) {
  SlidingBoundariesParams p = two_cells();
  p.dims = {4, 2};
  p.lower_bounds = {0.0, 0.0};
  p.upper_bounds = {4.0, 1.0};
  p.epsilon = 1e-6;
  SlidingBoundariesArchive a(p);
  EXPECT_EQ(a.cells(), 8);
  EXPECT_EQ(a.index_of(std::vector<double>{0.5, 0.2, 3.5, 0.9, -9.0, 9.0}), (std::vector<Index>{0, 7, 1}));
}

TEST(SlidingBoundariesArchive, RefusesBadSettingsNamingThem) {
  const auto refuses = [](SlidingBoundariesParams p, const std::string& words) {
    try {
      SlidingBoundariesArchive a(p);
      ADD_FAILURE() << "accepted; expected " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  SlidingBoundariesParams p = two_cells();
  p.upper_bounds = {0.0};
  refuses(p, "ranges[0] (0, 0)");
  p = two_cells();
  p.dims = {};
  refuses(p, "dims is empty");
  p = two_cells();
  p.remap_frequency = 0;
  refuses(p, "remap_frequency (0)");
}

}  // namespace
}  // namespace qdmeta
