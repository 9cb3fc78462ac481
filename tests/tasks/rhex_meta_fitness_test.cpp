// Tests of the RHex meta-fitnesses (src/qdmeta/tasks/rhex/rhex_meta_fitness.*) and of the
// `[task] name = "rhex"` config wiring (rhex_config.*): the meta-fitness is the mean of
// independently run episodes, the training sets are drawn as the paper says, and configs build.
#include <gtest/gtest.h>

#include <array>
#include <set>
#include <toml++/toml.h>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#include "qdmeta/tasks/rhex/rhex_meta_fitness.hpp"

namespace qdmeta {
namespace {

using rhex::DamageType;
using rhex::ObstacleCourse;
using rhex::RhexEnvironment;

RhexParams short_meta_params() {
  RhexParams p;
  p.episode.duration = 0.5;
  p.episode.settle_steps = 200;
  return p;
}

RowMatrix two_elites() {
  RowMatrix g(2, rhex::kGenes);
  g.row(0).setConstant(0.5f);
  g(0, 19) = 1.0f, g(0, 20) = 0.0f, g(0, 21) = 1.0f, g(0, 22) = 0.0f, g(0, 23) = 1.0f;  // tripod
  for (Index j = 0; j < rhex::kGenes; ++j) g(1, j) = static_cast<Real>((j * 7 % 11) / 10.0);
  return g;
}

TEST(RhexMetaFitness, DrawsDistinctTrainingSets) {
  Rng a(3), b(3);
  const auto types = draw_damage_types(a, 2);
  EXPECT_EQ(types, draw_damage_types(b, 2));
  ASSERT_EQ(types.size(), 2u);
  EXPECT_NE(types[0], types[1]);
  const auto envs = damage_environments(types);
  ASSERT_EQ(envs.size(), 12u);
  EXPECT_EQ(envs[0], RhexEnvironment::damaged(types[0], 0));
  EXPECT_EQ(envs[11], RhexEnvironment::damaged(types[1], 5));
  std::set<ObstacleCourse> seen;
  Rng c(5);
  for (ObstacleCourse course : draw_courses(c, 5)) {
    EXPECT_GE(static_cast<int>(course), 1);
    EXPECT_LE(static_cast<int>(course), 9);
    seen.insert(course);
  }
  EXPECT_EQ(seen.size(), 5u);
}

TEST(RhexMetaFitness, IsTheMeanDistanceOverSolutionsAndEnvironments) {
  const std::vector<RhexEnvironment> envs{RhexEnvironment::damaged(DamageType::kLegRemoval, 1),
                                          RhexEnvironment::obstacle(ObstacleCourse::kStairs)};
  const RhexTask task(short_meta_params());
  const RhexMetaFitness meta("rhex-test", {}, task, envs);
  const RowMatrix elites = two_elites();
  double expected = 0.0;
  for (Index s = 0; s < 2; ++s)
    for (const auto& e : envs) {
      const auto r = task.episode(elites.row(s).data(), e);
      expected += r.dead ? 0.0 : static_cast<double>(static_cast<Real>(r.fitness));  // the task's float fitness
    }
  expected /= 4.0;
  Rng rng(1);
  SerialEvaluator serial;
  const MetaFitnessResult one = meta.evaluate(elites, rng, serial);
  EXPECT_DOUBLE_EQ(one.value, expected);
  EXPECT_EQ(one.evaluations, 4);
  Rng rng2(1);
  const MetaFitnessResult two = meta.evaluate(elites, rng2, *make_thread_evaluator(2));
  EXPECT_EQ(one.value, two.value);  // same bits at any thread count

  const RhexMetaFitness half("rhex-test", {0.5}, task, envs);
  Rng rng3(1);
  EXPECT_EQ(half.evaluate(elites, rng3, serial).evaluations, 2);  // one solution x two environments
  Rng rng4(1);
  EXPECT_EQ(meta.evaluate(RowMatrix(0, rhex::kGenes), rng4, serial).evaluations, 0);
}

TEST(RhexConfig, SmokeConfigsBuildAndRecordTheDrawnSets) {
  register_rhex_task();
  for (const char* name :
       {"smoke-damage", "smoke-obstacle", "qdmeta-damage-trajectory", "qdmeta-obstacle-feature-sets",
        "qdmeta-damage-feature-sets", "qdmeta-obstacle-trajectory", "qdmeta-damage-trajectory-static",
        "qdmeta-obstacle-feature-sets-static", "qdmeta-damage-feature-sets-static", "qdmeta-obstacle-trajectory-static"}) {
    const std::string path = std::string(QDMETA_SOURCE_DIR) + "/configs/rhex/" + name + ".toml";
    const BuiltRun built = build_run(toml::parse_file(path), path, {});
    EXPECT_EQ(built.settings.counts, BudgetCount::kAll) << name;
    // The paper's conditions: SARSA(lambda) with RHex's reward scale by default, G = 5 for "-static".
    if (std::string(name).starts_with("qdmeta-")) {
      const bool fixed = std::string(name).ends_with("-static");
      EXPECT_EQ(built.resolved["control"]["kind"].value<std::string>(), fixed ? "static" : "sarsa") << name;
      if (fixed) EXPECT_EQ(built.resolved["control"]["generations"].value<std::int64_t>(), 5) << name;
      else EXPECT_EQ(built.resolved["control"]["reward_scale"].value<double>(), 24'096.0) << name;
    }
    const auto* meta = built.resolved["meta_fitness"].as_table();
    ASSERT_NE(meta, nullptr);
    const bool damage = std::string(name).find("damage") != std::string::npos;
    const auto* drawn = (*meta)[damage ? "damage_types" : "courses"].as_array();
    ASSERT_NE(drawn, nullptr) << name;
    EXPECT_EQ(static_cast<int>(drawn->size()), damage ? (std::string(name).starts_with("smoke") ? 1 : 2)
                                                      : (std::string(name).starts_with("smoke") ? 2 : 5));
  }
}

TEST(RhexConfig, BaselineConfigsBuildWithThePapersSettings) {
  register_rhex_task();
  for (const char* name : {"cvt-map-elites", "smoke-cvt", "aurora", "smoke-aurora"}) {
    const std::string path = std::string(QDMETA_SOURCE_DIR) + "/configs/rhex/" + name + ".toml";
    const BuiltRun built = build_run(toml::parse_file(path), path, {});  // builds; runs nothing
    EXPECT_EQ(built.settings.counts, BudgetCount::kAll) << name;
    const bool smoke = std::string(name).starts_with("smoke");
    EXPECT_EQ(built.settings.budget, smoke ? 1'000 : 12'000'000) << name;
    EXPECT_EQ(built.resolved["task"]["features"].value_or<std::string>(""), "trajectory") << name;
    if (std::string(name).find("cvt") != std::string::npos) {
      EXPECT_EQ(built.resolved["cvt"]["points"].value_or<std::string>(""), "random-descriptors") << name;
      EXPECT_EQ(built.resolved["cvt"]["centroids"].value_or<std::int64_t>(0), smoke ? 16 : 4096) << name;
      EXPECT_EQ(built.resolved["cvt"]["samples"].value_or<std::int64_t>(0), smoke ? 64 : 100'000) << name;
    } else {
      EXPECT_EQ(built.resolved["aurora"]["latent_size"].value_or<std::int64_t>(0), 4) << name;
      EXPECT_EQ(built.resolved["aurora"]["target_size"].value_or<std::int64_t>(0), smoke ? 32 : 4096) << name;
    }
  }
}

TEST(RhexConfig, BadKeysAreNamed) {
  register_rhex_task();
  const char* cases[][2] = {
      {"[task]\nname = \"rhex\"\nlegz = 1\n", "legz"},
      {"[task]\nname = \"rhex\"\nfeatures = \"joint\"\n", "task.features = \"joint\" is not a valid choice"},
      {"[task]\nname = \"rhex\"\nepisode_seconds = 0.503\n", "task.episode_seconds = 0.503"},
      {"algorithm = \"qd-meta\"\n[task]\nname = \"rhex\"\n[meta_fitness]\nkind = \"dimension\"\n",
       "meta_fitness.kind = \"dimension\" is not a valid choice: use one of \"damage\", \"obstacle\""},
      {"algorithm = \"qd-meta\"\n[task]\nname = \"rhex\"\n[meta_fitness]\ncourse_count = 2\nkind = \"obstacle\"\ncourses = [1, 10]\n",
       "meta_fitness.courses holds 10, out of range"},
      {"algorithm = \"cvt-map-elites\"\n[task]\nname = \"rhex\"\n[cvt]\npoints = \"trajectories\"\n",
       "cvt.points = \"trajectories\" is not a valid choice: use one of \"uniform\", \"random-descriptors\""},
  };
  for (const auto& c : cases) {
    const toml::table cfg = toml::parse(c[0]);
    try {
      build_run(cfg, "case.toml", {});
      ADD_FAILURE() << "no InputError for " << c[0];
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_TRUE(msg.starts_with("case.toml")) << msg;
      EXPECT_NE(msg.find(c[1]), std::string::npos) << msg;
    }
  }
}

}  // namespace
}  // namespace qdmeta
