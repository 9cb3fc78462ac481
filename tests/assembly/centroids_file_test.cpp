// cvt.centroids_file through a config: the run's archive has the file's centroids (no k-means,
// no cache), and a file of the wrong shape is refused naming the config, the key and the problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "expect_input_error.hpp"
#include "own_temp_path.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

toml::table config_with(const fs::path& file) {
  return toml::parse("algorithm = \"cvt-map-elites\"\n[task]\nname = \"rastrigin\"\ndimensions = 2\n"
                     "[cvt]\ncentroids = 3\ncache = false\ncentroids_file = \"" +
                     file.string() + "\"\n");
}

TEST(CentroidsFile, TheRunsArchiveHasTheFilesCentroids) {
  const fs::path file = test::own_temp_path("centroids_file_test_good.dat");
  std::ofstream(file) << "0.1 0.2\n0.5 0.5\n0.9 0.75\n";
  BuiltRun run = build_run(config_with(file), "c.toml");
  auto* cvt = dynamic_cast<CvtMapElites*>(run.algorithm.get());
  ASSERT_NE(cvt, nullptr);
  SerialEvaluator serial;
  cvt->prepare(serial);
  RowMatrix expected(3, 2);
  expected << 0.1f, 0.2f, 0.5f, 0.5f, 0.9f, 0.75f;
  EXPECT_TRUE(cvt->archive().centroids() == expected);
  EXPECT_EQ(run.resolved["cvt"]["centroids_file"].value<std::string>(), file.string());
}

TEST(CentroidsFile, AFileOfAnotherShapeIsRefusedNamingTheKey) {
  const fs::path file = test::own_temp_path("centroids_file_test_bad.dat");
  std::ofstream(file) << "0.1 0.2\n0.5 0.5\n";
  EXPECT_EQ(input_error_message([&] { (void)build_run(config_with(file), "c.toml"); }),
            "c.toml: cvt.centroids_file = \"" + file.string() + "\": 2 centroids, expected 3 (cvt.centroids)");
}

// Without the key, the resolved config has no centroids_file (checkpoint fingerprints unchanged).
TEST(CentroidsFile, AbsentKeyLeavesTheResolvedConfigAsBefore) {
  const BuiltRun run = build_run(toml::parse("algorithm = \"cvt-map-elites\"\n[cvt]\ncache = false\n"), "c.toml", {},
                                 BuildScope::kTasksOnly);
  EXPECT_FALSE(run.resolved["cvt"]["centroids_file"]);
}

}  // namespace
}  // namespace qdmeta
