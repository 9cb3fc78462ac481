// The proximity archive of novelty search: novelty, addition, local competition and threshold
// decay on cases worked by hand (the Python suite also holds it to pyribs's ProximityArchive).
#include "qdmeta/archive/proximity_archive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

ProximityArchiveParams line(Index k, double threshold) {
  ProximityArchiveParams p;
  p.solution_size = 1;
  p.measure_size = 1;
  p.k_neighbors = k;
  p.novelty_threshold = threshold;
  return p;
}

// Adds points on a line, each with solution = its position.
ProximityAddResult add(ProximityArchive& a, const std::vector<double>& at, const std::vector<double>& objectives) {
  return a.add(at, objectives, at);
}

TEST(ProximityArchive, AnEmptyArchiveTakesTheWholeBatchAtTheThresholdsNovelty) {
  ProximityArchive a(line(2, 0.5));
  const auto r = add(a, {0.0, 0.1}, {1.0, 2.0});  // close together, but judged against the empty archive
  EXPECT_EQ(r.status, (std::vector<std::uint8_t>{2, 2}));
  EXPECT_EQ(r.novelty, (std::vector<double>{0.5, 0.5}));
  EXPECT_EQ(a.size(), 2);
  EXPECT_TRUE(r.local_competition.empty() && r.value.empty());
}

TEST(ProximityArchive, NoveltyIsTheMeanDistanceToTheKNearestFewerWhileTheArchiveIsSmall) {
  ProximityArchive a(line(2, 0.0));
  add(a, {0.0}, {0.0});
  EXPECT_EQ(a.novelty(std::vector<double>{3.0}), (std::vector<double>{3.0}));  // one elite: k = 1
  add(a, {1.0, 4.0}, {0.0, 0.0});
  // Elites 0, 1, 4. From 3: distances 3, 2, 1 -> the two nearest 1 and 2 -> 1.5. From -1: 1, 2 -> 1.5.
  EXPECT_EQ(a.novelty(std::vector<double>{3.0, -1.0, 2.5}), (std::vector<double>{1.5, 1.5, 1.5}));
}

TEST(ProximityArchive, AddsWhatIsNovelEnoughAgainstTheArchiveBeforeTheBatch) {
  ProximityArchive a(line(1, 1.0));
  add(a, {0.0}, {5.0});
  // 0.5 is not novel; 1.0 is exactly the threshold (added); 3.0 and 3.2 are both novel against
  // the archive before the batch, though 0.2 apart.
  const auto r = add(a, {0.5, 1.0, 3.0, 3.2}, {9.0, 1.0, 1.0, 1.0});
  EXPECT_EQ(r.status, (std::vector<std::uint8_t>{0, 2, 2, 2}));
  EXPECT_EQ(a.size(), 4);
  EXPECT_EQ(std::vector<double>(a.measures().begin(), a.measures().end()), (std::vector<double>{0.0, 1.0, 3.0, 3.2}));
  EXPECT_EQ(a.objectives()[0], 5.0);  // without local competition nothing is replaced
}

TEST(ProximityArchive, LocalCompetitionReplacesTheNearestEliteWithTheBestCandidate) {
  ProximityArchiveParams p = line(1, 1.0);
  p.local_competition = true;
  ProximityArchive a(p);
  add(a, {0.0, 5.0}, {5.0, 1.0});
  // Candidates near elite 0 (objective 5): 0.2 with 7, 0.3 with 8 (both improve: the 8 wins),
  // 0.4 with 4 (does not); one novel at 10 (5 from its nearest); near elite 1: 5.1 with an equal 1.
  const auto r = add(a, {0.2, 0.3, 0.4, 10.0, 5.1}, {7.0, 8.0, 4.0, 3.0, 1.0});
  EXPECT_EQ(r.status, (std::vector<std::uint8_t>{1, 1, 0, 2, 0}));
  EXPECT_EQ(r.value, (std::vector<double>{2.0, 3.0, -1.0, 3.0, 0.0}));
  // Whether the nearest elite (k = 1) has a lower objective.
  EXPECT_EQ(r.local_competition, (std::vector<std::int32_t>{1, 1, 0, 1, 0}));
  EXPECT_EQ(std::vector<double>(a.objectives().begin(), a.objectives().end()), (std::vector<double>{8.0, 1.0, 3.0}));
  EXPECT_EQ(std::vector<double>(a.measures().begin(), a.measures().end()), (std::vector<double>{0.3, 5.0, 10.0}));
  EXPECT_EQ(a.solutions()[0], 0.3);
}

TEST(ProximityArchive, ThresholdDecaysAfterTheGivenNumberOfAddsWithNothingNovel) {
  ProximityArchiveParams p = line(1, 1.0);
  p.threshold_decay_rate = 0.5;
  p.threshold_decay_itrs = 2;
  p.threshold_decay_min = 0.3;
  ProximityArchive a(p);
  add(a, {0.0}, {0.0});
  add(a, {0.1}, {0.0});  // nothing novel: 1 of 2
  EXPECT_EQ(a.novelty_threshold(), 1.0);
  add(a, {0.1}, {0.0});  // 2 of 2: halved
  EXPECT_EQ(a.novelty_threshold(), 0.5);
  add(a, {0.9}, {0.0});  // novel: the count restarts
  add(a, {0.95}, {0.0});
  EXPECT_EQ(a.novelty_threshold(), 0.5);
  add(a, {0.95}, {0.0});
  EXPECT_EQ(a.novelty_threshold(), 0.3);  // 0.25, held at the minimum
}

TEST(ProximityArchive, IndexOfIsTheNearestEliteAndStatsCountEveryElite) {
  ProximityArchiveParams p = line(3, 0.0);
  p.qd_offset = -1.0;
  ProximityArchive a(p);
  add(a, {0.0, 2.0, 4.0}, {1.0, 3.0, 2.0});
  EXPECT_EQ(a.index_of(std::vector<double>{2.9, 3.1, -5.0}), (std::vector<Index>{1, 2, 0}));
  const ArchiveStats s = a.stats();
  EXPECT_EQ(s.num_elites, 3);
  EXPECT_EQ(s.coverage, 1.0);
  EXPECT_EQ(s.qd_score, 6.0 + 3.0);
  EXPECT_EQ(s.obj_max, 3.0);
}

TEST(ProximityArchive, RefusesBadSettingsAndBatchesNamingThem) {
  const auto refuses = [](ProximityArchiveParams p, const std::string& words) {
    try {
      ProximityArchive a(p);
      ADD_FAILURE() << "accepted; expected " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  ProximityArchiveParams p = line(0, 1.0);
  refuses(p, "k_neighbors (0)");
  p = line(1, -1.0);
  refuses(p, "novelty_threshold (-1)");
  p = line(1, 1.0);
  p.threshold_decay_rate = 1.5;
  refuses(p, "threshold_decay_rate (1.5)");
  p.threshold_decay_rate = 0.5;
  p.threshold_decay_itrs = 0;
  refuses(p, "threshold_decay_itrs (0)");
  ProximityArchive a(line(1, 1.0));
  EXPECT_THROW(a.add(std::vector<double>{0.0}, std::vector<double>{NAN}, std::vector<double>{0.0}), InputError);
  EXPECT_THROW(a.add(std::vector<double>{0.0, 1.0}, std::vector<double>{0.0}, std::vector<double>{0.0}), InputError);
  EXPECT_THROW(a.index_of(std::vector<double>{0.0}), InputError);  // empty
  EXPECT_EQ(a.size(), 0);
}

}  // namespace
}  // namespace qdmeta
