// summary.json written and read back by its one reader (src/qdmeta/run/summary.hpp): every key in
// the writer's order with its type (whole numbers, numbers, text, null for a number that was not
// finite), nothing when there is no summary, and a one-line InputError naming the file for
// anything that is not a summary.
#include "qdmeta/run/summary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/run/run_tables.hpp"
#include "run/run_dir_fixture.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

using SummaryTest = test::RunDirFixture;

TEST_F(SummaryTest, WhatWriteSummaryWroteReadsBackKeyByKey) {
  RunResult result;
  result.reason = StopReason::kInterrupted;
  result.message = "stopped by a signal";
  result.counters.bottom = 12'000;
  result.counters.meta = 345;
  result.evals = 12'000;
  result.generations = 30;
  result.stats = {1234, 0.1234, 5678.5, 0.5678, -0.25, std::numeric_limits<double>::quiet_NaN()};
  result.wall_seconds = 2.0;
  RunSettings settings;
  settings.task = "rastrigin";
  settings.seed = 7;
  settings.budget = 20'000;
  write_summary(dir_ / "summary.json", {result, settings, "qd-meta", 2, {{"trainings", 3.0}}});

  const std::optional<RunSummary> s = read_summary(dir_);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->stop_reason, StopReason::kInterrupted);
  EXPECT_EQ(stop_reason_of(dir_), StopReason::kInterrupted);  // 0.2.0's name for it
  std::vector<std::string> keys, expected;
  for (const auto& [key, value] : s->values) keys.push_back(key);
  for (const auto& c : summary_head_table().columns()) expected.emplace_back(c.key());
  for (const auto& c : metrics_table().columns()) expected.emplace_back(c.key());
  expected.emplace_back("trainings");
  for (const auto& c : summary_tail_table().columns()) expected.emplace_back(c.key());
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(std::get<std::string>(*s->find("algorithm")), "qd-meta");
  EXPECT_EQ(std::get<std::string>(*s->find("message")), "stopped by a signal");
  EXPECT_EQ(s->integer("seed"), 7);
  EXPECT_EQ(s->integer("budget"), 20'000);
  EXPECT_EQ(s->integer("evals_meta"), 345);
  EXPECT_EQ(s->integer("generations"), 30);
  EXPECT_EQ(s->integer("num_elites"), 1234);
  EXPECT_EQ(s->integer("threads"), 2);
  EXPECT_EQ(std::get<double>(*s->find("coverage")), 0.1234);  // the same double, through the text
  EXPECT_EQ(std::get<double>(*s->find("obj_max")), -0.25);
  EXPECT_EQ(std::get<double>(*s->find("trainings")), 3.0);  // a number, though whole
  EXPECT_EQ(std::get<double>(*s->find("evals_per_second")), 12'345 / 2.0);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(*s->find("obj_mean")));  // NaN is written as null
  EXPECT_EQ(s->integer("coverage"), std::nullopt);  // not whole
  EXPECT_EQ(s->integer("no_such_key"), std::nullopt);
  EXPECT_EQ(s->find("no_such_key"), nullptr);
}

TEST_F(SummaryTest, NoSummaryIsNothing) {
  EXPECT_FALSE(read_summary(dir_).has_value());
  EXPECT_FALSE(read_summary(dir_ / "missing").has_value());
  EXPECT_FALSE(stop_reason_of(dir_).has_value());
}

TEST_F(SummaryTest, ASummaryOfAnOlderProgramNeedsOnlyItsStopReason) {
  write("summary.json", "{\"stop_reason\": \"budget\", \"evals\": 100}");
  const std::optional<RunSummary> s = read_summary(dir_);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->stop_reason, StopReason::kBudget);
  EXPECT_EQ(s->values.size(), 2u);
  EXPECT_EQ(s->integer("budget"), std::nullopt);
}

TEST_F(SummaryTest, AnythingElseIsAnInputErrorNamingTheFile) {
  const std::string file = (dir_ / "summary.json").string();
  const struct {
    std::string text, why;
  } cases[] = {
      {"{\"stop_reason\": ", "parse error"},
      {"[\"budget\"]", "not a JSON object"},
      {"{\"evals\": 100}", "stop_reason is missing or not text"},
      {"{\"stop_reason\": 3}", "stop_reason is missing or not text"},
      {"{\"stop_reason\": \"tired\"}", "stop_reason"},
      {"{\"stop_reason\": \"budget\", \"config\": {\"seed\": 1}}", "'config' holds neither a number nor text"},
      {"{\"stop_reason\": \"budget\", \"done\": true}", "'done' holds neither a number nor text"},
  };
  for (const auto& c : cases) {
    write("summary.json", c.text);
    const std::string message = input_error_message([&] { (void)read_summary(dir_); });
    EXPECT_TRUE(message.starts_with(file + " is unreadable: ")) << c.text << "\n" << message;
    EXPECT_NE(message.find(c.why), std::string::npos) << c.text << "\n" << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(ParseSummary, AKeptSummarysTextIsReadTheSameWay) {
  const RunSummary s = parse_summary("{\"stop_reason\": \"budget\", \"budget\": 5000, \"obj_max\": null}", "kept.json");
  EXPECT_EQ(s.stop_reason, StopReason::kBudget);
  EXPECT_EQ(s.integer("budget"), 5000);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(*s.find("obj_max")));
  EXPECT_TRUE(input_error_message([] { (void)parse_summary("{}", "kept.json"); }).starts_with("kept.json is unreadable: "));
}

}  // namespace
}  // namespace qdmeta
