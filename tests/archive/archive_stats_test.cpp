// The meta-population summary of archive statistics: hand-computed means and standard errors.
#include "qdmeta/archive/archive_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

ArchiveStats stats(Index elites, double mean, double max, double qd) {
  ArchiveStats s;
  s.num_elites = elites;
  s.obj_mean = mean;
  s.obj_max = max;
  s.qd_score = qd;
  return s;
}

TEST(PopulationStats, MeanAndStandardErrorOfEachStatistic) {
  // Sizes 2, 4, 9: mean 5, squared deviations 9 + 1 + 16 = 26, sample variance 13, SE sqrt(13 / 3).
  // Average fitness -1, -2, -3: mean -2, sample variance 1, SE 1 / sqrt(3).
  const std::vector<ArchiveStats> maps = {stats(2, -1, 0.5, 10), stats(4, -2, 0.5, 10), stats(9, -3, 0.5, 40)};
  const PopulationStats p = population_stats(maps);
  EXPECT_DOUBLE_EQ(p.num_elites.mean, 5.0);
  EXPECT_DOUBLE_EQ(p.num_elites.se, std::sqrt(13.0 / 3.0));
  EXPECT_DOUBLE_EQ(p.obj_mean.mean, -2.0);
  EXPECT_DOUBLE_EQ(p.obj_mean.se, 1.0 / std::sqrt(3.0));
  EXPECT_EQ(p.obj_max.mean, 0.5);  // identical values: no spread
  EXPECT_EQ(p.obj_max.se, 0.0);
  // QD-scores 10, 10, 40: mean 20, sample variance (100 + 100 + 400) / 2 = 300, SE 10.
  EXPECT_DOUBLE_EQ(p.qd_score.mean, 20.0);
  EXPECT_DOUBLE_EQ(p.qd_score.se, 10.0);
}

TEST(PopulationStats, OneMapHasNoStandardError) {
  const std::vector<ArchiveStats> one = {stats(7, -80, -20, 900)};
  const PopulationStats p = population_stats(one);
  EXPECT_EQ(p.num_elites, (MeanSe{7, 0}));
  EXPECT_EQ(p.obj_mean, (MeanSe{-80, 0}));
  EXPECT_EQ(p.obj_max, (MeanSe{-20, 0}));
  EXPECT_EQ(p.qd_score, (MeanSe{900, 0}));
}

TEST(PopulationStats, NoMapsIsAnError) {
  EXPECT_THROW(population_stats(std::vector<ArchiveStats>{}), Error);
}

}  // namespace
}  // namespace qdmeta
