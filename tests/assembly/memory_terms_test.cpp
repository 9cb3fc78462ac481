// The memory each algorithm says it will allocate (core/memory_estimate.hpp), as build_run
// collects it, against sizes worked out here from the config: the terms that grow with the
// config's largest keys must grow with exactly them.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "qdmeta/assembly/build.hpp"

namespace qdmeta {
namespace {

double term(const BuiltRun& built, std::string_view what) {
  for (const MemoryTerm& t : built.memory.terms)
    if (t.what == what) return t.bytes;
  ADD_FAILURE() << "no memory term '" << what << "'";
  return -1;
}

BuiltRun tasks_only(const std::string& config) {
  return build_run(toml::parse(config), "x.toml", {}, BuildScope::kTasksOnly);
}

// Genotypes, then fitness, base features and validity, 4 bytes each, per offspring row.
double row_bytes(const Task& task) { return 4.0 * static_cast<double>(2 * task.genotype_size() + task.base_feature_size() + 2); }

TEST(MemoryTerms, QdMetaOffspringGrowWithTheLargestGenerationCountTheControllerMayChoose) {
  const std::string head = "algorithm = \"qd-meta\"\n[task]\ndimensions = 6\n[qd_meta]\nmeta_population = 5\nbatch_size = 10\n";
  const BuiltRun fixed = tasks_only(head + "[control]\nkind = \"static\"\ngenerations = 7\n");
  const Task& task = fixed.evaluation_tasks.front();
  EXPECT_DOUBLE_EQ(term(fixed, "every map's offspring of one meta-generation"), 5 * 7 * 10 * row_bytes(task));
  const BuiltRun learnt = tasks_only(head + "[control]\nkind = \"sarsa\"\nmin_generations = 2\nmax_generations = 12\n");
  EXPECT_DOUBLE_EQ(term(learnt, "every map's offspring of one meta-generation"), 5 * 12 * 10 * row_bytes(task));
  // The database: capacity x (genes + 2 base features + 1 fitness), floats.
  EXPECT_DOUBLE_EQ(term(fixed, "the circular database"),
                   500'000 * 4.0 * static_cast<double>(task.genotype_size() + 2 * task.base_feature_size() + 1));
}

TEST(MemoryTerms, AMapElitesArchiveIsItsCellsTimesWhatACellHolds) {
  const BuiltRun built = tasks_only("[task]\ndimensions = 6\n[archive]\nbins = [8, 16]\n");
  const Task& task = built.evaluation_tasks.front();
  // Per cell: objective (4), occupied flag (1), solution and the two measures (4 each).
  EXPECT_DOUBLE_EQ(term(built, "the archive"), 8 * 16 * (4 + 1 + 4.0 * static_cast<double>(task.genotype_size() + 2)));
  EXPECT_DOUBLE_EQ(term(built, "a generation's offspring"), 2000 * row_bytes(task));  // the initial population
}

}  // namespace
}  // namespace qdmeta
