// Tests of the gait export (src/qdmeta/tasks/rhex/gait_export.*): every recorded step becomes a
// CSV row, the HTML page embeds the subsampled frames, and an episode without poses is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "own_temp_path.hpp"
#include "qdmeta/tasks/rhex/gait_export.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta::rhex {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

EpisodeResult recorded_walk() {
  RhexParams p;
  p.episode.duration = 0.5;
  p.episode.settle_steps = 50;
  p.episode.record_poses = true;
  std::array<Real, kGenes> g{};
  g.fill(0.5f);
  return RhexTask(p).episode(g.data(), {});
}

TEST(GaitExport, CsvHasOneRowPerStep) {
  const EpisodeResult r = recorded_walk();
  ASSERT_EQ(static_cast<int>(r.poses.size()), r.walk_steps + r.settle_steps);
  EXPECT_DOUBLE_EQ(r.poses.front().time, 0.005);
  EXPECT_NEAR(r.poses[99].time, 0.5, 1e-12);
  EXPECT_NEAR(r.poses.back().position[0] - r.fitness, 0.0, 1e-9);  // start x is 0
  const fs::path path = test::own_temp_path("gait_test.csv");
  write_gait_csv(r, path);
  const std::string text = slurp(path);
  EXPECT_TRUE(text.starts_with("time,x,y,z,roll,pitch,yaw,leg_0,leg_1,leg_2,leg_3,leg_4,leg_5\n"));
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), static_cast<long>(r.poses.size()) + 1);
}

TEST(GaitExport, HtmlEmbedsSubsampledFrames) {
  const EpisodeResult r = recorded_walk();
  const fs::path path = test::own_temp_path("gait_test.html");
  write_gait_html(r, path, "tripod test", 10);
  const std::string text = slurp(path);
  EXPECT_NE(text.find("<title>tripod test</title>"), std::string::npos);
  const auto at = text.find("const frames = [[");
  ASSERT_NE(at, std::string::npos);
  const std::string frames = text.substr(at, text.find("]];", at) - at);
  EXPECT_EQ(std::count(frames.begin(), frames.end(), '['), 1 + static_cast<long>((r.poses.size() + 9) / 10));
}

TEST(GaitExport, RefusesAnEpisodeWithoutPoses) {
  EpisodeResult r;
  EXPECT_THROW(write_gait_csv(r, test::own_temp_path("gait_test_empty.csv")), InputError);
}

}  // namespace
}  // namespace qdmeta::rhex
