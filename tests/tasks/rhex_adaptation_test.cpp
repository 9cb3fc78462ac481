// Tests of the RHex test phase (src/qdmeta/tasks/rhex/rhex_adaptation.* and its wiring in
// rhex_config.cpp): the test families are the complements of the training sets the meta-fitness
// draws, whatever the run trained on, and scores are episodes in the damaged environment.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <toml++/toml.h>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_adaptation.hpp"
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#include "qdmeta/tasks/rhex/rhex_meta_fitness.hpp"

namespace qdmeta {
namespace {

using rhex::DamageType;
using rhex::ObstacleCourse;
using rhex::RhexEnvironment;

// A run's config as `qdmeta run` resolves it (algorithm, seed, [task], and for QD-Meta the
// drawn training set).
toml::table run_config(const std::string& algorithm, const std::string& meta_kind, std::int64_t seed) {
  std::string text = "algorithm = \"" + algorithm + "\"\nseed = " + std::to_string(seed) +
                     "\n[task]\nname = \"rhex\"\nepisode_seconds = 0.5\nsettle_steps = 100\n";
  if (algorithm == "qd-meta") text += "[qd_meta]\ndatabase_capacity = 100\n";  // no 500,000-row database
  if (algorithm == "qd-meta") text += "[meta_fitness]\nkind = \"" + meta_kind + "\"\n";
  const BuiltRun built = build_run(toml::parse(text), "run.toml", {});
  return built.resolved;
}

std::vector<RhexEnvironment> environments(const toml::table& config, const std::string& test) {
  const auto tests = build_adaptation_tests(config, "run.toml", test, 99);
  const auto* rhex_tests = dynamic_cast<const RhexAdaptationTests*>(tests.get());
  EXPECT_NE(rhex_tests, nullptr);
  EXPECT_EQ(tests->default_budget(), 50);
  return rhex_tests ? rhex_tests->environments() : std::vector<RhexEnvironment>{};
}

std::set<std::string> names(const std::vector<RhexEnvironment>& envs) {
  std::set<std::string> out;
  for (const auto& e : envs) out.insert(e.to_string());
  return out;
}

TEST(RhexAdaptation, TestFamiliesAreTheComplementOfTheTrainingDraw) {
  register_rhex_task();
  for (std::int64_t seed : {1, 2, 3, 7, 12}) {
    // What QD-Meta Damage and Obstacle train on with this seed (their resolved configs' draws).
    const toml::table damage_run = run_config("qd-meta", "damage", seed);
    const toml::table obstacle_run = run_config("qd-meta", "obstacle", seed);
    std::set<int> trained_types;
    for (const auto& v : *damage_run["meta_fitness"]["damage_types"].as_array()) trained_types.insert(*v.value<int>());
    std::set<int> trained_courses;
    for (const auto& v : *obstacle_run["meta_fitness"]["courses"].as_array()) trained_courses.insert(*v.value<int>());
    ASSERT_EQ(trained_types.size(), 2u);
    ASSERT_EQ(trained_courses.size(), 5u);

    // Every run of this seed, QD-Meta of either kind or a baseline, meets the same partition.
    for (const toml::table& config : {damage_run, obstacle_run, run_config("map-elites", "", seed)}) {
      const auto test_damage = environments(config, "damage");
      const auto train_damage = environments(config, "damage-training");
      ASSERT_EQ(test_damage.size(), 12u) << "seed " << seed;
      ASSERT_EQ(train_damage.size(), 12u);
      std::set<int> test_types;
      std::set<std::pair<int, int>> cells;  // (type, leg)
      for (const auto& e : test_damage) {
        EXPECT_EQ(e.course, ObstacleCourse::kFlat);
        test_types.insert(static_cast<int>(e.damage));
        cells.insert({static_cast<int>(e.damage), e.leg});
      }
      EXPECT_EQ(cells.size(), 12u);  // 2 types x 6 legs, no repeats
      for (int t : test_types) EXPECT_FALSE(trained_types.contains(t)) << "seed " << seed << " type " << t;
      EXPECT_EQ(test_types.size(), 2u);
      for (const auto& e : train_damage) EXPECT_TRUE(trained_types.contains(static_cast<int>(e.damage)));

      const auto test_courses = environments(config, "obstacle");
      const auto train_courses = environments(config, "obstacle-training");
      ASSERT_EQ(test_courses.size(), 4u);
      ASSERT_EQ(train_courses.size(), 5u);
      std::set<int> all;
      for (const auto& e : test_courses) {
        EXPECT_EQ(e.damage, DamageType::kNone);
        EXPECT_FALSE(trained_courses.contains(static_cast<int>(e.course))) << "seed " << seed;
        all.insert(static_cast<int>(e.course));
      }
      for (const auto& e : train_courses) {
        EXPECT_TRUE(trained_courses.contains(static_cast<int>(e.course)));
        all.insert(static_cast<int>(e.course));
      }
      EXPECT_EQ(all.size(), 9u);  // together: every course once
    }
  }
}

TEST(RhexAdaptation, FollowsTheRunsOwnTrainingSet) {
  register_rhex_task();
  // A run that trained on one damage type (as the smoke config) is tested on the other three.
  const toml::table config = toml::parse(
      "algorithm = \"qd-meta\"\nseed = 4\n[task]\nname = \"rhex\"\n[meta_fitness]\nkind = \"damage\"\n"
      "damage_type_count = 1\ndamage_types = [3]\n");
  const auto test = environments(config, "damage");
  EXPECT_EQ(test.size(), 18u);
  for (const auto& e : test) EXPECT_NE(e.damage, DamageType::kBlockedHip);
  const auto training = environments(config, "damage-training");
  EXPECT_EQ(names(training), names(damage_environments({DamageType::kBlockedHip})));
}

TEST(RhexAdaptation, UnknownTestsListTheValidOnes) {
  register_rhex_task();
  try {
    build_adaptation_tests(run_config("map-elites", "", 1), "run.toml", "dimension", 1);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown test 'dimension' for task 'rhex': valid tests are damage, obstacle, damage-training, "
              "obstacle-training, generalisation");
  }
  const auto groups = build_generalisation_groups(run_config("map-elites", "", 1), "run.toml", 1);
  ASSERT_EQ(groups.size(), 4u);
  EXPECT_EQ(groups[0]->name(), "damage-training");
  EXPECT_EQ(groups[1]->name(), "obstacle-training");
  EXPECT_EQ(groups[2]->name(), "damage");
  EXPECT_EQ(groups[3]->name(), "obstacle");
}

// 4 episodes of 1 s: a removed front leg changes a walking tripod's distance; the score is the
// episode's forward distance, run through the evaluator.
TEST(RhexAdaptation, ADamagedLegChangesTheScoreOfAWalkingController) {
  RhexParams p;
  p.episode.duration = 1.0;
  p.episode.settle_steps = 200;
  const RhexTask task(p);
  RowMatrix tripod(1, rhex::kGenes);
  tripod.row(0).setConstant(0.5f);
  tripod(0, 19) = 1.0f, tripod(0, 20) = 0.0f, tripod(0, 21) = 1.0f, tripod(0, 22) = 0.0f, tripod(0, 23) = 1.0f;
  const RhexAdaptationTests tests("damage", task,
                                  {RhexEnvironment{}, RhexEnvironment::damaged(DamageType::kLegRemoval, 2),
                                   RhexEnvironment::damaged(DamageType::kBlockedHip, 1)});
  auto evaluator = make_thread_evaluator(2);
  std::vector<double> intact(1), removed(1), blocked(1);
  tests.score(0, tripod, *evaluator, intact);
  tests.score(1, tripod, *evaluator, removed);
  tests.score(2, tripod, *evaluator, blocked);
  const auto episode = task.episode(tripod.row(0).data(), RhexEnvironment::damaged(DamageType::kLegRemoval, 2));
  EXPECT_EQ(removed[0], episode.dead ? 0.0 : episode.fitness);
  EXPECT_GT(intact[0], 0.2);  // it walks
  EXPECT_GT(std::abs(intact[0] - removed[0]), 0.02) << intact[0] << " vs " << removed[0];
  EXPECT_GT(std::abs(intact[0] - blocked[0]), 0.02) << intact[0] << " vs " << blocked[0];
}

}  // namespace
}  // namespace qdmeta
