#include "qdmeta/tasks/rastrigin/rastrigin_config.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"
#include "qdmeta/tasks/rastrigin/test_functions.hpp"

namespace qdmeta {
namespace {

RastriginParams read_rastrigin_params(ConfigReader& t) {
  RastriginParams p;
  p.dimensions = static_cast<int>(t.integer(RastriginParams::kDimensions, p.dimensions));
  p.score_m = t.number(RastriginParams::kScoreM, p.score_m);
  return p;
}

Task read_rastrigin_task(ConfigReader& t) { return Task(RastriginTask(read_rastrigin_params(t))); }

TaskShape read_rastrigin_shape(ConfigReader& t) {
  const RastriginParams p = read_rastrigin_params(t);
  naming_source(t, [&] { p.validate(); });
  return RastriginTask::shape_of(p);
}

// The keys both meta-fitnesses share; M is the task's.
RastriginMetaParams read_common(ConfigReader& m, const Task& task) {
  RastriginMetaParams p;
  p.sample_fraction = m.number(RastriginMetaParams::kSampleFraction, p.sample_fraction);
  p.score_m = task.qd_offset() < 0 ? -task.qd_offset() : p.score_m;
  return p;
}

// The dimensions J are drawn once per replicate from the seed and written to the resolved
// config, so that the resolved file repeats the run.
std::unique_ptr<MetaObjective> read_dimension_meta(ConfigReader& m, const Task& task, std::uint64_t seed) {
  RastriginMetaParams p = read_common(m, task);
  const auto n = task.genotype_size();
  p.dimension_count = static_cast<int>(m.integer(RastriginMetaParams::kDimensionCount, p.dimension_count));
  IntParam at_most_genes = RastriginMetaParams::kDimensionCount;  // |J| <= N as well
  at_most_genes.hi = n;
  naming_source(m, [&] { require(at_most_genes, p.dimension_count); });
  std::vector<std::int64_t> drawn;
  Rng rng = Rng::stream(seed, {key(StreamKey::kMetaFitness), 0xD1D1});
  for (int d : rastrigin::sample_dimensions(rng, static_cast<int>(n), p.dimension_count)) drawn.push_back(d);
  const auto given = m.integers("dimensions", drawn, 0, n - 1, static_cast<std::size_t>(p.dimension_count),
                                static_cast<std::size_t>(p.dimension_count), "dimension_count distinct entries in [0, N)");
  std::vector<int> dims(given.begin(), given.end());
  return naming_source(m, [&]() -> std::unique_ptr<MetaObjective> {
    if (m.resolving()) {
      RastriginDimensionMeta::validate(p, dims);
      return nullptr;
    }
    p.validate();
    return std::make_unique<RastriginDimensionMeta>(p, dims);
  });
}

std::unique_ptr<MetaObjective> read_translation_meta(ConfigReader& m, const Task& task, std::uint64_t) {
  RastriginMetaParams p = read_common(m, task);
  p.transform_repetitions = static_cast<int>(m.integer(RastriginMetaParams::kTransformRepetitions, p.transform_repetitions));
  p.transform_per_solution = m.boolean("transform_per_solution", p.transform_per_solution);
  return naming_source(m, [&]() -> std::unique_ptr<MetaObjective> {
    p.validate();
    if (m.resolving()) return nullptr;
    return std::make_unique<RastriginTranslationMeta>(p);
  });
}

std::unique_ptr<AdaptationTests> read_rastrigin_tests(const toml::table&, const std::string&, const Task& task,
                                                      std::string_view test, std::uint64_t seed) {
  const auto n = static_cast<int>(task.genotype_size());
  const double m = -task.qd_offset();  // Rastrigin's offset is -M
  if (test == "dimension") {
    // One stream for drawing the pairs, apart from the per-function search streams.
    Rng rng = Rng::stream(seed, {key(StreamKey::kTest), 0xD1D1'0000'0000'0000ULL});
    return std::make_unique<RastriginDimensionTests>(n, 120, rng, m);
  }
  return std::make_unique<RastriginTranslationTests>(n, m);
}

}  // namespace

void register_rastrigin_task() {
  TaskPlugin plugin;
  plugin.read_task = read_rastrigin_task;
  plugin.read_shape = read_rastrigin_shape;
  plugin.meta_objectives = {{"translation", read_translation_meta}, {"dimension", read_dimension_meta}};
  plugin.read_adaptation_tests = read_rastrigin_tests;
  plugin.adaptation_tests = {"dimension", "translation"};
  register_task_plugin("rastrigin", std::move(plugin));
}

}  // namespace qdmeta
