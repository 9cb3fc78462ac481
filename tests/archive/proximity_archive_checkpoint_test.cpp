// ProximityArchive's checkpoints (save/load): a loaded archive continues to the same bits as the
// original, the threshold's decay count included; a checkpoint of other sizes is refused.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/archive/proximity_archive.hpp"

namespace qdmeta {
namespace {

// A 1-D archive whose threshold decays after two adds in a row with nothing novel.
ProximityArchiveParams decaying() {
  ProximityArchiveParams p;
  p.solution_size = 1;
  p.measure_size = 1;
  p.k_neighbors = 1;
  p.novelty_threshold = 1.0;
  p.threshold_decay_rate = 0.5;
  p.threshold_decay_itrs = 2;
  return p;
}

std::string saved(const ProximityArchive& a) {
  BinaryWriter out;
  a.save(out);
  return out.bytes();
}

void add_point(ProximityArchive& a, double at) { a.add(std::vector{at}, std::vector{at}, std::vector{at}); }

TEST(ProximityArchiveCheckpoint, ALoadedArchiveContinuesToTheSameBitsDecayCountIncluded) {
  ProximityArchive a(decaying());
  add_point(a, 0.0);
  add_point(a, 5.0);
  add_point(a, 0.2);  // not novel: one add of the two before a decay
  ProximityArchive b(decaying());
  const std::string checkpoint = saved(a);  // the reader views it
  BinaryReader in(checkpoint, "test");
  b.load(in);
  in.finish();
  EXPECT_EQ(saved(b), saved(a));
  add_point(a, 0.3);  // the second in a row: the threshold halves in both
  add_point(b, 0.3);
  EXPECT_EQ(a.novelty_threshold(), 0.5);
  EXPECT_EQ(saved(b), saved(a));
  add_point(a, 0.9);  // novel at 0.5 (0.9 from 0, its nearest elite), not at 1
  add_point(b, 0.9);
  EXPECT_EQ(b.size(), 3);
  EXPECT_EQ(saved(b), saved(a));
}

TEST(ProximityArchiveCheckpoint, RefusesAnArchiveOfOtherSizes) {
  ProximityArchive a(decaying());
  add_point(a, 0.0);
  auto other = decaying();
  other.measure_size = 2;
  ProximityArchive b(other);
  const std::string checkpoint = saved(a);
  BinaryReader in(checkpoint, "test");
  const std::string message = input_error_message([&] { b.load(in); });
  EXPECT_NE(message.find("the saved proximity archive has 1 genes and 1 measures; this one 1 and 2"), std::string::npos) << message;
}

}  // namespace
}  // namespace qdmeta
