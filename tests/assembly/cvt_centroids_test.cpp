// A run's CVT centroids (assembly/cvt_centroids.hpp): made once by k-means and cached, read
// back from the cache afterwards (the cached values, not new ones), the same bits on any number
// of threads; random-descriptor points only where the task's genotypes are valid.
#include "qdmeta/assembly/cvt_centroids.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/io/centroid_cache.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

// Valid only where the first gene is >= 0.5; its base features are its genes.
struct RightHalfTask {
  Index genotype_size() const { return 2; }
  Index base_feature_size() const { return 2; }
  bool shareable() const { return true; }
  void evaluate(GenotypeView g, EvaluationView out) const {
    for (Index i = 0; i < g.count; ++i) {
      out.valid[i] = g.row(i)[0] >= 0.5f;
      out.fitness[i] = 0.0;
      for (Index j = 0; j < 2; ++j) out.base_row(i)[j] = out.valid[i] ? g.row(i)[j] : std::nanf("");
    }
  }
};

KMeansParams small() {
  KMeansParams k;
  k.centroids = 10;
  k.samples = 300;
  k.init_samples = 300;
  k.iterations = 3;
  return k;
}

std::size_t files_in(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(dir)) n += entry.is_regular_file() ? 1 : 0;
  return n;
}

TEST(CvtCentroids, RandomDescriptorsAreCachedAndReadBackAsCached) {
  const fs::path dir = fs::temp_directory_path() / ("qdmeta_cvt_centroids_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  CvtCentroidSettings settings;
  settings.cache_dir = dir;
  settings.points = CvtPoints::kRandomDescriptors;
  settings.task_key = "right-half";
  const Task task(RightHalfTask{});
  const RowMatrix made = cvt_centroid_source(settings, small(), task)(nullptr);
  ASSERT_EQ(made.rows(), 10);
  ASSERT_EQ(made.cols(), 2);
  for (Index i = 0; i < made.rows(); ++i) EXPECT_GE(made(i, 0), 0.5f);  // means of valid points
  EXPECT_EQ(files_in(dir), 1U);
  auto threads = make_evaluator(2);
  EXPECT_TRUE(cvt_centroid_source(settings, small(), task)(threads.get()) == made);

  // A hit returns the file's centroids: overwrite them with known values under the same key.
  const std::string key = centroid_cache_key(2, small()) + "-desc-right-half";
  RowMatrix planted = RowMatrix::Constant(10, 2, 0.75f);
  write_centroid_file(dir / (key + ".bin"), key, planted);
  EXPECT_TRUE(cvt_centroid_source(settings, small(), task)(nullptr) == planted);

  settings.points = CvtPoints::kUniform;  // uniform points reach below 0.5, under another key
  const RowMatrix uniform = cvt_centroid_source(settings, small(), task)(nullptr);
  EXPECT_LT(uniform.col(0).minCoeff(), 0.5f);
  EXPECT_EQ(files_in(dir), 2U);
  fs::remove_all(dir);
}

TEST(CvtCentroids, WithoutACacheNothingIsWritten) {
  const Task task(RightHalfTask{});
  const RowMatrix a = cvt_centroid_source({}, small(), task)(nullptr);
  auto threads = make_evaluator(2);
  EXPECT_TRUE(cvt_centroid_source({}, small(), task)(threads.get()) == a);
  EXPECT_TRUE(a == cvt_centroids(2, small()).centroids);  // k-means over uniform points, as the algorithm's default
}

}  // namespace
}  // namespace qdmeta
