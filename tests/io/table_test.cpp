// Output tables: the header and the rows come from one declaration; numbers print as before.
#include "qdmeta/io/table.hpp"

#include <gtest/gtest.h>

#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "own_temp_path.hpp"
#include "qdmeta/experiment/adaptation.hpp"
#include "qdmeta/run/run_tables.hpp"

namespace qdmeta {
namespace {

struct Sample {
  std::int64_t count;
  double value;
  std::string label;
};

const Table<Sample>& sample_table() {
  static const Table<Sample> table = {
      {"count", [](const Sample& s) { return Cell(s.count); }},
      {"value", [](const Sample& s) { return Cell(s.value); }, "value_key"},
      {"label", [](const Sample& s) { return Cell(s.label); }},
  };
  return table;
}

TEST(Table, HeaderAndRowsComeFromTheSameColumns) {
  const auto& t = sample_table();
  EXPECT_EQ(t.header(), (std::vector<std::string>{"count", "value", "label"}));
  EXPECT_EQ(t.row({-3, 0.1, "x"}), (std::vector<std::string>{"-3", "0.1", "x"}));
  EXPECT_EQ(t.row({0, 0.1, ""}).size(), t.header().size());
}

TEST(Table, SummaryKeyDefaultsToTheColumnName) {
  const auto& c = sample_table().columns();
  EXPECT_EQ(c[0].key(), "count");
  EXPECT_EQ(c[1].key(), "value_key");
}

TEST(Table, CellsPrintIntegersAsIntegersAndDoublesInTheirShortestRoundTripForm) {
  EXPECT_EQ(cell_text(Cell(std::int64_t{12345678901234})), "12345678901234");
  EXPECT_EQ(cell_text(Cell(std::uint64_t{18446744073709551615u})), "18446744073709551615");
  EXPECT_EQ(cell_text(Cell(0.30000000000000004)), "0.30000000000000004");
  EXPECT_EQ(cell_text(Cell(1.0)), "1");
  EXPECT_EQ(cell_text(Cell(1e-7)), "1e-07");
  EXPECT_EQ(cell_text(Cell(std::nan(""))), "nan");
}

TEST(RunTables, MetricsAndMetaHeadersAreTheFilesHistoricalOnes) {
  // Resume checks these against files written before the tables existed (meta.csv gained the
  // population columns with checkpoint format 3).
  EXPECT_EQ(fmt::format("{}", fmt::join(metrics_columns(), ",")),
            "evals,evals_bottom,evals_meta,generation,num_elites,coverage,qd_score,norm_qd_score,obj_max,obj_mean");
  EXPECT_EQ(fmt::format("{}", fmt::join(meta_columns(), ",")),
            "meta_generation,evals,evals_bottom,evals_meta,meta_fitness_best,meta_fitness_mean,meta_fitness_sd,"
            "generations,states,population_num_elites_mean,population_num_elites_se,population_obj_mean_mean,"
            "population_obj_mean_se,population_obj_max_mean,population_obj_max_se,population_qd_score_mean,"
            "population_qd_score_se");
}

TEST(RunTables, AMetricsRowHoldsEveryFieldOfItsPointInHeaderOrder) {
  RunPoint p;
  p.evals = 10400;
  p.counters = {10000, 400};
  p.generation = 22;
  p.stats = {7, 0.25, 3.5, 0.125, 1.5, -0.75};
  EXPECT_EQ(metrics_table().row(p),
            (std::vector<std::string>{"10400", "10000", "400", "22", "7", "0.25", "3.5", "0.125", "1.5", "-0.75"}));
  EXPECT_EQ(metrics_table().columns()[3].key(), "generations");  // summary.json's historical key
}

TEST(RunTables, AMetaRowHoldsTheRecordAndTheCounters) {
  MetaGenerationRecord r;
  r.meta_generation = 3;
  r.meta_fitness_best = 0.5;
  r.meta_fitness_mean = 0.25;
  r.meta_fitness_sd = 0.125;
  r.generations = 10;
  r.states = 2;
  r.population = {{120, 4}, {-80.5, 1.25}, {-20, 0.5}, {9000, 30}};
  EXPECT_EQ(meta_table().row(MetaPoint{r, {900, 100}, 1000}),
            (std::vector<std::string>{"3", "1000", "900", "100", "0.5", "0.25", "0.125", "10", "2", "120", "4", "-80.5",
                                      "1.25", "-20", "0.5", "9000", "30"}));
}

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(TestPhaseTables, AdaptationAndGeneralisationFilesKeepTheirFormat) {
  const auto dir = test::own_temp_path("table_test");
  std::filesystem::create_directories(dir);
  AdaptationCurve curve;
  curve.best_mean = {-2.5, 0.1};
  curve.best_se = {0.5, 0.0};
  write_adaptation_csv(dir / "adapt.csv", curve);
  EXPECT_EQ(slurp(dir / "adapt.csv"), "evaluations,best_mean,best_se\n1,-2.5,0.5\n2,0.1,0\n");
  write_generalisation_csv(dir / "generalisation.csv", {{"damage-test", 6, 40, 1.25, 0.125}});
  EXPECT_EQ(slurp(dir / "generalisation.csv"), "group,environments,solutions,mean,se\ndamage-test,6,40,1.25,0.125\n");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace qdmeta
