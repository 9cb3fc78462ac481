// Tests of the parts a config names by kind (src/qdmeta/plugin/part_registries.hpp): a registered
// variation operator, controller, feature-map and archive are found by name, read their own keys
// (a misspelt one is refused), and give the results their definitions say; a variation operator
// handed over as a part needs no registration. Registrations use names of their own, so the
// tests do not disturb each other.
#include "qdmeta/plugin/part_registries.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/core_plugins.hpp"
#include "qdmeta/assembly/run_parts.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/plugin/config.hpp"

// `statement` throws an InputError whose message starts with `prefix`.
#define EXPECT_ERROR_STARTS(statement, prefix)                                                  \
  do {                                                                                           \
    const std::string message_ = ::qdmeta::input_error_message([&] { statement; });              \
    EXPECT_TRUE(message_.starts_with(prefix)) << #statement << "\n  threw: " << message_;      \
  } while (false)

namespace qdmeta {
namespace {

// Rastrigin MAP-Elites on a small grid, with `extra` TOML appended.
toml::table map_elites_config(const std::string& extra) {
  return toml::parse(
      "algorithm = \"map-elites\"\nseed = 7\n[task]\nname = \"rastrigin\"\ndimensions = 6\n"
      "[archive]\nbins = [12, 12]\n[map_elites]\nbatch_size = 50\ninitial_population = 100\n" +
      extra);
}

EliteTable run_generations(Algorithm& algorithm, int generations, int threads) {
  auto evaluator = threads == 1 ? std::unique_ptr<Evaluator>(std::make_unique<SerialEvaluator>())
                                : make_thread_evaluator(threads);
  for (int g = 0; g < generations; ++g) algorithm.step(*evaluator);
  return algorithm.elites();
}

void expect_same_elites(const EliteTable& a, const EliteTable& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.objective, b.objective);
  EXPECT_EQ(a.solutions, b.solutions);
  EXPECT_EQ(a.measures, b.measures);
}

// The test's operator: offspring = parent + scale (partner - parent), genes clamped; it also
// moves gene 0 by a uniform draw from its seed, so that the seed matters.
VariationFunction blend(double scale, std::atomic<int>* calls) {
  return [scale, calls](const RowMatrix& parents, const RowMatrix& partners, std::uint64_t seed, RowMatrix& out) {
    if (calls) ++*calls;
    Rng rng(seed);
    for (Index r = 0; r < out.rows(); ++r)
      for (Index k = 0; k < out.cols(); ++k) {
        double g = parents(r, k) + scale * (partners(r, k) - parents(r, k));
        if (k == 0) g += 0.05 * (rng.uniform() - 0.5);
        out(r, k) = static_cast<Real>(std::clamp(g, 0.0, 1.0));
      }
  };
}

std::atomic<int> blend_calls{0};

void register_test_parts() {
  ensure_core_plugins();
  variation_registry().add("test-blend", [](ConfigReader& m, const Task&) {
    return blend(m.number("scale", 0.5, 0.0, 1.0), &blend_calls);
  });
  variation_registry().add("test-out-of-range", [](ConfigReader&, const Task&) -> VariationFunction {
    return [](const RowMatrix&, const RowMatrix&, std::uint64_t, RowMatrix& out) { out.setConstant(1.5f); };
  });
}

TEST(RegisteredVariation, MakesMapElitesOffspringAsTheSameOperatorSetByHand) {
  register_test_parts();
  const BuiltRun built = build_run(map_elites_config("[mutation]\nkind = \"test-blend\"\nscale = 0.3\n"), "x.toml");
  EXPECT_EQ(built.resolved["mutation"]["kind"].value<std::string>(), "test-blend");
  EXPECT_EQ(built.resolved["mutation"]["scale"].value<double>(), 0.3);
  blend_calls = 0;
  const EliteTable from_config = run_generations(*built.algorithm, 12, 1);
  EXPECT_EQ(blend_calls, 11);  // every generation but the random first

  // The same operator handed to MapElites in code: the same bits.
  BuiltRun by_hand = build_run(map_elites_config(""), "x.toml");
  auto* map_elites = dynamic_cast<MapElites*>(by_hand.algorithm.get());
  ASSERT_NE(map_elites, nullptr);
  map_elites->set_variation(blend(0.3, nullptr));
  expect_same_elites(from_config, run_generations(*map_elites, 12, 1));

  // Its key matters, and a key of the built-in kinds is unknown to it.
  const BuiltRun other = build_run(map_elites_config("[mutation]\nkind = \"test-blend\"\nscale = 0.9\n"), "x.toml");
  EXPECT_NE(run_generations(*other.algorithm, 12, 1).objective, from_config.objective);
  EXPECT_ERROR_STARTS(build_run(map_elites_config("[mutation]\nkind = \"test-blend\"\nsigma = 0.1\n"), "x.toml"),
                     "x.toml: unknown key 'mutation.sigma' in [mutation]");
  EXPECT_ERROR_STARTS(build_run(map_elites_config("[mutation]\nkind = \"test-blend\"\nscale = 2\n"), "x.toml"),
                     "x.toml: mutation.scale = 2 is out of range");
}

TEST(RegisteredVariation, ServesEveryBuiltInAlgorithmWithTheSameBitsAtAnyThreadCount) {
  register_test_parts();
  const std::string mutation = "[mutation]\nkind = \"test-blend\"\n";
  const std::vector<std::string> configs = {
      "algorithm = \"cvt-map-elites\"\n[task]\ndimensions = 4\n[cvt]\ncentroids = 50\nsamples = 2000\ncache = false\n"
      "[map_elites]\nbatch_size = 40\ninitial_population = 80\n",
      "algorithm = \"qd-meta\"\n[task]\ndimensions = 4\n[archive]\nbins = [5, 5]\n[qd_meta]\nmeta_population = 3\n"
      "batch_size = 20\ninitial_population = 40\ndatabase_capacity = 2000\n[control]\nkind = \"static\"\n"
      "generations = 2\n",
      "algorithm = \"aurora\"\n[task]\ndimensions = 4\n[aurora]\nbatch_size = 40\ninitial_population = 80\n"
      "max_epochs = 3\ntarget_size = 50\n",
  };
  for (const auto& text : configs) {
    std::vector<EliteTable> runs;
    for (int threads : {1, 3}) {
      const BuiltRun built = build_run(toml::parse(text + mutation), "x.toml");
      blend_calls = 0;
      runs.push_back(run_generations(*built.algorithm, 4, threads));
      EXPECT_GT(blend_calls, 0) << text;
    }
    expect_same_elites(runs[0], runs[1]);
  }
}

TEST(RegisteredVariation, OffspringOutsideTheUnitBoxStopTheRunNamingTheOperator) {
  register_test_parts();
  const BuiltRun built = build_run(map_elites_config("[mutation]\nkind = \"test-out-of-range\"\n"), "x.toml");
  SerialEvaluator evaluator;
  built.algorithm->step(evaluator);  // the random first generation
  EXPECT_ERROR_STARTS(built.algorithm->step(evaluator),
                     "mutation kind \"test-out-of-range\" wrote gene 0 = 1.5 of offspring 0: genes must be in [0, 1]");
  EXPECT_EQ(built.algorithm->generation(), 1);  // the failed step was undone
}

TEST(RegisteredVariation, AnUnknownKindListsTheBuiltInAndRegisteredOnes) {
  register_test_parts();
  const std::string msg = input_error_message([] { build_run(map_elites_config("[mutation]\nkind = \"blend\"\n"), "x.toml"); });
  EXPECT_TRUE(msg.starts_with("x.toml: mutation.kind = \"blend\" is not a valid choice: use one of \"gaussian\", "
                              "\"discrete-step\", \"uniform-resample\", \"iso-line\""))
      << msg;
  EXPECT_NE(msg.find("\"test-blend\""), std::string::npos) << msg;
}

TEST(RegisteredVariation, ABuiltInKindCannotBeRegisteredOver) {
  register_test_parts();
  variation_registry().add("iso-line", [](ConfigReader&, const Task&) { return blend(0.5, nullptr); });
  EXPECT_ERROR_STARTS(build_run(map_elites_config(""), "x.toml"),
                      "x.toml: this program registered a part under \"iso-line\", a built-in kind of this table");
  variation_registry().remove("iso-line");
  EXPECT_NE(build_run(map_elites_config(""), "x.toml").algorithm, nullptr);
}

TEST(VariationPart, IsUsedWithoutRegisteringAndTheConfigOnlyNamesIt) {
  ensure_core_plugins();
  RunParts parts;
  std::atomic<int> calls{0};
  parts.variation = VariationPart{"part-blend", [&calls](ConfigReader&, const Task&) { return blend(0.3, &calls); }};
  const BuiltRun built = build_run(map_elites_config(""), "x.toml", {}, parts);
  EXPECT_EQ(built.resolved["mutation"]["kind"].value<std::string>(), "part-blend");
  EXPECT_FALSE(variation_registry().contains("part-blend"));
  const EliteTable from_part = run_generations(*built.algorithm, 12, 1);
  EXPECT_EQ(calls, 11);
  BuiltRun by_hand = build_run(map_elites_config(""), "x.toml");
  dynamic_cast<MapElites&>(*by_hand.algorithm).set_variation(blend(0.3, nullptr));
  expect_same_elites(from_part, run_generations(*by_hand.algorithm, 12, 1));
  EXPECT_ERROR_STARTS(build_run(map_elites_config("[mutation]\nkind = \"gaussian\"\n"), "x.toml", {}, parts),
                     "x.toml: mutation.kind = \"gaussian\" is not a valid choice: use one of \"part-blend\"");
  // The part reads its own keys, and their errors name the file once.
  parts.variation->read = [](ConfigReader& m, const Task&) { return blend(m.number("scale", 0.5, 0.0, 1.0), nullptr); };
  EXPECT_INPUT_ERROR(build_run(map_elites_config("[mutation]\nscale = 3\n"), "x.toml", {}, parts),
                     "x.toml: mutation.scale = 3 is out of range: must be in [0, 1]");
}

// A controller that alternates G = 1, 2, 1, ... and counts what it is told.
class Alternate final : public GenerationController {
 public:
  explicit Alternate(int first) : next_(first) {}
  std::string name() const override { return "test-alternate"; }
  int choose_generations(const Eigen::MatrixXd&, Rng&) override {
    const int g = next_;
    next_ = 3 - next_;
    chosen.push_back(g);
    return g;
  }
  int max_generations() const override { return 2; }
  void observe(std::span<const double>, std::int64_t evaluations) override { observed += evaluations; }
  void save(BinaryWriter& out) const override { out.value(next_); }
  void load(BinaryReader& in) override { next_ = in.value<int>("next"); }
  inline static std::vector<int> chosen;
  inline static std::int64_t observed = 0;

 private:
  int next_;
};

TEST(RegisteredController, ChoosesQdMetasGenerations) {
  ensure_core_plugins();
  controller_registry().add("test-alternate", [](ConfigReader& c) -> std::unique_ptr<GenerationController> {
    return std::make_unique<Alternate>(static_cast<int>(c.integer("first", 1, 1, 2)));
  });
  const std::string text =
      "algorithm = \"qd-meta\"\n[task]\ndimensions = 4\n[archive]\nbins = [5, 5]\n[qd_meta]\nmeta_population = 2\n"
      "batch_size = 10\ninitial_population = 20\ndatabase_capacity = 1000\n[control]\nkind = \"test-alternate\"\n";
  const BuiltRun built = build_run(toml::parse(text + "first = 2\n"), "x.toml");
  Alternate::chosen.clear();
  Alternate::observed = 0;
  SerialEvaluator evaluator;
  const std::int64_t before = built.algorithm->counters().bottom;
  for (int t = 0; t < 4; ++t) built.algorithm->step(evaluator);
  EXPECT_EQ(Alternate::chosen, (std::vector<int>{2, 1, 2, 1}));
  // Each meta-generation evaluates meta_population x G x batch_size offspring, and the
  // controller is told them; the first also evaluates the initial population.
  EXPECT_EQ(Alternate::observed, 2 * (2 + 1 + 2 + 1) * 10);
  EXPECT_EQ(built.algorithm->counters().bottom - before, Alternate::observed + 20);
  EXPECT_ERROR_STARTS(build_run(toml::parse(text + "generations = 2\n"), "x.toml"),
                     "x.toml: unknown key 'control.generations' in [control]");
  const std::string msg = input_error_message([&] {
    build_run(toml::parse("algorithm = \"qd-meta\"\n[control]\nkind = \"alternate\"\n"), "x.toml");
  });
  EXPECT_TRUE(msg.starts_with("x.toml: control.kind = \"alternate\" is not a valid choice: use one of \"static\", "
                              "\"sarsa\", "))
      << msg;
}

// Target features: the mean of the first half of the base features, then of the second half.
class HalfMeans final : public FeatureMap {
 public:
  explicit HalfMeans(Index inputs) : inputs_(inputs) {}
  Index input_size() const override { return inputs_; }
  Index output_size() const override { return 2; }
  void map(const Real* base, Index count, Real* target) const override {
    const Index half = inputs_ / 2;
    for (Index r = 0; r < count; ++r) {
      double a = 0, b = 0;
      for (Index k = 0; k < inputs_; ++k) (k < half ? a : b) += base[r * inputs_ + k];
      target[2 * r] = static_cast<Real>(a / half);
      target[2 * r + 1] = static_cast<Real>(b / (inputs_ - half));
    }
  }

 private:
  Index inputs_;
};

TEST(RegisteredFeatureMap, GivesMapElitesItsMeasures) {
  ensure_core_plugins();
  feature_map_registry().add("test-half-means", [](ConfigReader&, Index base, Index targets) -> std::unique_ptr<FeatureMap> {
    if (targets != 2) throw InputError("test-half-means makes 2 target features");
    return std::make_unique<HalfMeans>(base);
  });
  const BuiltRun built = build_run(map_elites_config("[feature_map]\nkind = \"test-half-means\"\n"), "x.toml");
  const EliteTable elites = run_generations(*built.algorithm, 6, 1);
  ASSERT_GT(elites.size(), 10);
  // Each elite's measures are the map of its base features, recomputed here from the task.
  const Task& task = built.evaluation_tasks.front();
  EvaluationBatch eval;
  eval.resize(elites.size(), task.base_feature_size());
  task.evaluate({elites.solutions.data(), elites.size(), task.genotype_size()}, eval.view());
  RowMatrix expected(elites.size(), 2);
  HalfMeans(task.base_feature_size()).map(eval.base_features.data(), elites.size(), expected.data());
  EXPECT_EQ(elites.measures, expected);
  EXPECT_ERROR_STARTS(build_run(map_elites_config("[feature_map]\nkind = \"test-half-means\"\nscale = 1\n"), "x.toml"),
                     "x.toml: unknown key 'feature_map.scale' in [feature_map]");
  EXPECT_ERROR_STARTS(build_run(toml::parse("[archive]\nbins = [4, 4, 4]\n[feature_map]\nkind = \"test-half-means\"\n"),
                               "x.toml"),
                     "x.toml: test-half-means makes 2 target features");
  toml::table picked = map_elites_config("[feature_map]\nkind = \"test-half-means\"\n");
  picked["archive"].as_table()->insert_or_assign("measures", toml::array{0, 1});
  EXPECT_ERROR_STARTS(build_run(picked, "x.toml"),
                     "x.toml: archive.measures picks base features for feature_map.kind = \"select\"");
}

TEST(RegisteredFeatureMap, IsRefusedWhereTheAlgorithmMakesItsOwnDescriptors) {
  ensure_core_plugins();
  EXPECT_ERROR_STARTS(build_run(toml::parse("algorithm = \"qd-meta\"\n[feature_map]\nkind = \"select\"\n"), "x.toml"),
                     "x.toml: [feature_map] does not apply to algorithm \"qd-meta\": it evolves its own neural "
                     "feature-maps");
  EXPECT_ERROR_STARTS(build_run(toml::parse("algorithm = \"cvt-map-elites\"\n[feature_map]\n"), "x.toml"),
                     "x.toml: [feature_map] does not apply to algorithm \"cvt-map-elites\"");
  EXPECT_ERROR_STARTS(build_run(toml::parse("algorithm = \"qd-meta\"\n[archive]\nkind = \"other\"\n"), "x.toml"),
                     "x.toml: archive.kind = \"other\" is not a valid choice: use one of \"grid\"");
}

TEST(RegisteredArchive, RunsMapElitesThroughAnyArchiveWithTheGridsBits) {
  ensure_core_plugins();
  archive_registry().add("test-wrapped-grid", [](ConfigReader& a, const ArchiveShape& shape, MemoryEstimate& memory) {
    GridArchiveParams p;
    const auto side = static_cast<int>(a.integer("side", 10, 1, 1000));
    p.bins = {side, side};
    p.solution_size = shape.solution_size;
    p.qd_offset = shape.qd_offset;
    memory.add("the test's archive", "side^2 x genes", grid_archive_bytes(p));
    return AnyArchive(GridArchive(p));
  });
  toml::table cfg = map_elites_config("");
  cfg.insert_or_assign("archive", toml::table{{"kind", "test-wrapped-grid"}, {"side", 12}});
  const BuiltRun wrapped = build_run(cfg, "x.toml");
  ASSERT_NE(dynamic_cast<BasicMapElites<AnyArchive>*>(wrapped.algorithm.get()), nullptr);
  EXPECT_GT(wrapped.memory.total(), 0.0);
  const BuiltRun grid = build_run(map_elites_config(""), "x.toml");
  ASSERT_NE(dynamic_cast<MapElites*>(grid.algorithm.get()), nullptr);
  const EliteTable a = run_generations(*wrapped.algorithm, 8, 1);
  expect_same_elites(a, run_generations(*grid.algorithm, 8, 1));

  // A checkpoint goes through the wrapped archive: saved, loaded into a fresh run, equal again.
  BinaryWriter out;
  wrapped.algorithm->save(out);
  const BuiltRun loaded = build_run(cfg, "x.toml");
  BinaryReader in(out.bytes(), "checkpoint");
  loaded.algorithm->load(in);
  expect_same_elites(loaded.algorithm->elites(), a);
  EXPECT_EQ(run_generations(*loaded.algorithm, 2, 1).objective, run_generations(*wrapped.algorithm, 2, 1).objective);

  cfg.insert_or_assign("archive", toml::table{{"kind", "test-wrapped-grid"}, {"bins", toml::array{12, 12}}});
  EXPECT_ERROR_STARTS(build_run(cfg, "x.toml"), "x.toml: unknown key 'archive.bins' in [archive]");
}

}  // namespace
}  // namespace qdmeta
