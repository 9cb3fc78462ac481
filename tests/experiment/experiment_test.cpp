// Experiment files: conditions, overrides, and one-line errors for what is wrong in them.
#include "qdmeta/experiment/experiment.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>

#include "../expect_input_error.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/experiment/test_phase.hpp"
#include "qdmeta/run/run_directory.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

fs::path write(const std::string& name, const std::string& text) {
  // One folder per process: ctest runs the tests of this file as parallel processes.
  const fs::path dir = fs::temp_directory_path() / ("qdmeta_experiment_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "run.toml") << "algorithm = \"map-elites\"\n";
  const fs::path path = dir / (name + ".toml");
  std::ofstream(path) << text;
  return path;
}

TEST(Experiment, ReadsConditionsRelativeToTheFileWithOverrides) {
  const fs::path f = write("good", R"(name = "demo"
replicates = 3
tests = ["dimension"]
[[condition]]
name = "Plain MAP-Elites"
config = "run.toml"
[[condition]]
name = "Small budget"
config = "run.toml"
set = { budget = { evaluations = 1234 } }
)");
  const ExperimentSpec s = load_experiment(f, std::nullopt, std::nullopt);
  EXPECT_EQ(s.name, "demo");
  EXPECT_EQ(s.replicates, 3);
  EXPECT_EQ(s.tests, std::vector<std::string>{"dimension"});
  ASSERT_EQ(s.conditions.size(), 2u);
  EXPECT_EQ(s.conditions[0].slug, "plain-map-elites");
  EXPECT_EQ(s.conditions[0].config, f.parent_path() / "run.toml");
  EXPECT_EQ(s.conditions[1].effective_config()["budget"]["evaluations"].value<std::int64_t>(), 1234);
  EXPECT_EQ(s.conditions[1].effective_config()["algorithm"].value<std::string>(), "map-elites");
  EXPECT_EQ(replicate_dir("/out", s.conditions[1], 2), fs::path("/out/small-budget/seed-2"));
  const ExperimentSpec o = load_experiment(f, 5, 777);
  EXPECT_EQ(o.replicates, 5);
  EXPECT_EQ(o.evaluations, 777);
}

TEST(Experiment, ShippedExperimentFilesLoad) {
  const fs::path dir = fs::path(QDMETA_SOURCE_DIR) / "configs/rastrigin";
  const auto sigma = [](const ExperimentCondition& c) { return c.effective_config()["mutation"]["sigma"].value<double>(); };
  // The headline study: the paper's four conditions and QD-Meta Translation's frozen control at
  // the authors' effective mutation SD, with the paper's claims.
  const ExperimentSpec paper = load_experiment(dir / "experiment.toml", std::nullopt, std::nullopt);
  EXPECT_EQ(paper.replicates, 20);
  ASSERT_EQ(paper.conditions.size(), 5u);
  EXPECT_EQ(paper.conditions[4].slug, "qd-meta-translation-frozen-cma-es");
  EXPECT_EQ(paper.claims.size(), 11u);  // 10 of the paper's and the frozen control's (source = "ours")
  for (const auto& c : paper.conditions) EXPECT_EQ(sigma(c), 0.0025) << c.name;
  // The meta-population-size study (Fig S1) at the same SD.
  const ExperimentSpec lambda = load_experiment(dir / "experiment-lambda.toml", std::nullopt, std::nullopt);
  EXPECT_EQ(lambda.replicates, 20);
  ASSERT_EQ(lambda.conditions.size(), 6u);  // lambda in {1, 2, 3, 5, 10, 20}
  EXPECT_EQ(lambda.claims.size(), 5u);
  for (const auto& c : lambda.conditions) EXPECT_EQ(sigma(c), 0.0025) << c.name;
  EXPECT_EQ(lambda.conditions[4].effective_config()["qd_meta"]["meta_population"].value<std::int64_t>(), 10);
  // The paper's four conditions at its stated SD.
  const ExperimentSpec stated = load_experiment(dir / "experiment-stated-sd.toml", std::nullopt, std::nullopt);
  EXPECT_EQ(stated.replicates, 20);
  ASSERT_EQ(stated.conditions.size(), 4u);
  EXPECT_EQ(stated.claims.size(), 10u);  // all but the frozen control's
  for (std::size_t i = 0; i < stated.conditions.size(); ++i) {
    EXPECT_EQ(stated.conditions[i].slug, paper.conditions[i].slug);
    EXPECT_EQ(sigma(stated.conditions[i]), 0.05);
  }
  // QD-Meta over CMA-MAE: the headline study's QD-Meta conditions but for their bottom level (and
  // [mutation] and qd_meta.batch_size, which it replaces by 10 emitters of 40 rows), and CMA-MAE
  // alone, all at the headline study's budget.
  const ExperimentSpec inner = load_experiment(dir / "experiment-cma-mae-inner.toml", std::nullopt, std::nullopt);
  EXPECT_EQ(inner.replicates, 10);
  ASSERT_EQ(inner.conditions.size(), 3u);
  EXPECT_EQ(inner.conditions[0].slug, "qd-meta-translation-cma-mae");
  EXPECT_EQ(inner.conditions[1].slug, "qd-meta-dimension-cma-mae");
  for (std::size_t i = 0; i < 2; ++i) {
    toml::table ours = inner.conditions[i].effective_config();
    toml::table gaussian = paper.conditions[1 - i].effective_config();  // Translation, Dimension
    EXPECT_EQ(ours["qd_meta"]["bottom_level"].value<std::string>(), "cma-mae");
    EXPECT_EQ(ours["emitters"]["count"].value_or(0) * ours["emitters"]["batch_size"].value_or(0),
              gaussian["qd_meta"]["batch_size"].value_or(-1));
    for (toml::table* t : {&ours, &gaussian}) {
      for (const char* table : {"emitters", "mutation"}) t->erase(table);
      for (const char* key : {"bottom_level", "batch_size"}) t->get_as<toml::table>("qd_meta")->erase(key);
      for (const char* key : {"learning_rate", "threshold_min"}) t->get_as<toml::table>("archive")->erase(key);
    }
    EXPECT_EQ(ours, gaussian) << inner.conditions[i].name;
  }
  EXPECT_EQ(inner.conditions[2].effective_config()["algorithm"].value<std::string>(), "cma-mae");
  for (const auto& c : inner.conditions)
    EXPECT_EQ(c.effective_config()["budget"]["evaluations"].value<std::int64_t>(), 100'000'000) << c.name;
}

std::string file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// An experiment tests each run from the archive it holds in memory; `qdmeta adapt` reads it
// back from archive.csv. Both must give the same bytes (archive.csv keeps every float exactly).
TEST(Experiment, TestsOfAFreshRunMatchTestsReadFromItsArchiveFile) {
  const fs::path f = write("tested", "replicates = 1\nevaluations = 3000\ntests = [\"dimension\", \"translation\"]\n"
                                     "[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  const fs::path out = f.parent_path() / "tested-out";
  fs::remove_all(out);
  const ExperimentSpec spec = load_experiment(f, std::nullopt, std::nullopt);
  const ExperimentResult r = run_experiment(spec, out, 1, {}, nullptr);
  ASSERT_EQ(r.tests_done, 2);
  const fs::path dir = replicate_dir(out, spec.conditions[0], 1);
  auto evaluator = make_evaluator(1);
  for (const std::string test : {"dimension", "translation"}) {
    const fs::path csv = dir / ("adapt-" + test + ".csv");
    const std::string from_memory = file_text(csv);
    ASSERT_FALSE(from_memory.empty());
    fs::remove(csv);
    adapt_run(RunState(dir), test, std::nullopt, std::nullopt, *evaluator);
    EXPECT_EQ(file_text(csv), from_memory) << test;
  }
  fs::remove_all(out);
}

TEST(Experiment, ReplicateRangesAreAOrAToB) {
  EXPECT_EQ(parse_replicate_range("6-10").first, 6);
  EXPECT_EQ(parse_replicate_range("6-10").last, 10);
  EXPECT_EQ(parse_replicate_range("3").first, 3);
  EXPECT_EQ(parse_replicate_range("3").last, 3);
  EXPECT_EQ(parse_replicate_range("4-4").last, 4);
  for (const char* bad : {"", "0", "0-3", "5-2", "-3", "3-", "a-b", "1-2-3", "1 - 2", "+1", "2-x", "99999999999"})
    EXPECT_INPUT_ERROR(parse_replicate_range(bad), std::string("replicates '") + bad +
                                                       "' must be a range A-B or one replicate A, with 1 <= A <= B");
}

TEST(Experiment, BadFilesAreOneLineErrors) {
  const auto error_of = [](const fs::path& f) {
    try {
      load_experiment(f, std::nullopt, std::nullopt);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  fs::path f = write("typo", "replicate = 2\n[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f), f.string() + ": unknown key 'replicate' at the top level (valid keys: claim, condition, "
                                      "evaluations, generalisation_solutions, name, replicates, tests)");
  f = write("condition-typo", "[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n[[condition]]\nname = \"b\"\n"
                              "config = \"run.toml\"\nsets = {}\n");
  EXPECT_EQ(error_of(f), f.string() + ": unknown key 'condition[2].sets' in [condition[2]] (valid keys: config, name, set)");
  f = write("tests", "tests = \"dimension\"\n[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f), f.string() + ": tests must be an array of strings, got a string");
  f = write("sample", "generalisation_solutions = 0\n[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f),
            f.string() + ": generalisation_solutions = 0 is out of range: must be in [1, 9223372036854775807]");
  f = write("none", "replicates = 2\n");
  EXPECT_EQ(error_of(f), f.string() + ": no [[condition]] tables: an experiment needs at least one");
  f = write("missing", "[[condition]]\nname = \"a\"\nconfig = \"nowhere.toml\"\n");
  EXPECT_NE(error_of(f).find("condition 'a' names a config that does not exist"), std::string::npos) << error_of(f);
  f = write("twice", "[[condition]]\nname = \"A b\"\nconfig = \"run.toml\"\n[[condition]]\nname = \"a-B\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f), f.string() + ": condition 'a-B' repeats another's name");
  f = write("zero", "replicates = 0\n[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f), f.string() + ": replicates = 0 is out of range: must be in [1, 100000]");
  f = write("claim", "claim = 3\n[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f), f.string() + ": claim must be an array of tables ([[claim]]), got a integer");
  f = write("claimless", "[[claim]]\ntext = \"x\"\n[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f), f.string() + ":1:1: [[claim]] 1: missing key 'kind'");
  // A claim is checked against the conditions, wherever they come in the file; the message
  // points at the value that breaks the rule.
  f = write("unknown-condition", "tests = [\"dimension\"]\n[[claim]]\ntext = \"x\"\nkind = \"top\"\n"
                                 "measure = \"test:dimension@10\"\nconditions = [\"a\", \"b\"]\ntop = \"a\"\n"
                                 "[[condition]]\nname = \"a\"\nconfig = \"run.toml\"\n");
  EXPECT_EQ(error_of(f), f.string() + ":6:14: [[claim]] 1: unknown condition 'b' (conditions: a)");
}

}  // namespace
}  // namespace qdmeta
