// Tests of src/qdmeta/io/centroid_cache.{hpp,cpp}: a hit returns the same bits, any key change
// misses, a damaged file is regenerated with a warning (never used), and the key's format.
#include "qdmeta/io/centroid_cache.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "own_temp_path.hpp"
#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = test::own_temp_path("centroid_cache_test_" + name);
  fs::remove_all(dir);
  return dir;
}

KMeansParams small() {
  KMeansParams p;
  p.centroids = 20;
  p.samples = 2000;
  p.init_samples = 1000;
  p.iterations = 3;
  return p;
}

TEST(CentroidCache, TheKeyNamesEveryParameter) {
  EXPECT_EQ(centroid_cache_key(20, KMeansParams{}), "cvt-d20-k10000-n1000000-init-k-means++100000-lloyd-i10-s1");
  KMeansParams p = small();
  p.method = KMeansMethod::kMiniBatch;
  p.init = KMeansInit::kRandom;
  p.seed = 7;
  EXPECT_EQ(centroid_cache_key(3, p), "cvt-d3-k20-n2000-init-random-mini-batch-i3-b100000-s7");
}

TEST(CentroidCache, MissThenHitWithTheSameBits) {
  const fs::path dir = fresh_dir("hit") / "nested";
  const CachedCentroids first = load_or_make_centroids(3, small(), dir);
  EXPECT_EQ(first.outcome, CacheOutcome::kMiss);
  EXPECT_TRUE(fs::exists(first.path));
  EXPECT_EQ(first.path.parent_path(), dir);
  EXPECT_FALSE(first.cost.empty());
  const CachedCentroids second = load_or_make_centroids(3, small(), dir);
  EXPECT_EQ(second.outcome, CacheOutcome::kHit);
  EXPECT_TRUE(second.centroids == first.centroids);
  EXPECT_TRUE(second.cost.empty());  // k-means did not run
  EXPECT_TRUE(cvt_centroids(3, small()).centroids == first.centroids);
}

TEST(CentroidCache, AnyKeyChangeMisses) {
  const fs::path dir = fresh_dir("keys");
  const CachedCentroids base = load_or_make_centroids(3, small(), dir);
  std::vector<KMeansParams> changed(5, small());
  changed[0].seed = 2;
  changed[1].centroids = 21;
  changed[2].samples = 2001;
  changed[3].iterations = 4;
  changed[4].method = KMeansMethod::kMiniBatch;
  for (const KMeansParams& p : changed) {
    const CachedCentroids c = load_or_make_centroids(3, p, dir);
    EXPECT_EQ(c.outcome, CacheOutcome::kMiss) << c.path;
    EXPECT_NE(c.path, base.path);
    EXPECT_FALSE(c.centroids.rows() == base.centroids.rows() && c.centroids == base.centroids);
  }
  EXPECT_EQ(load_or_make_centroids(4, small(), dir).outcome, CacheOutcome::kMiss);  // dimension
  EXPECT_EQ(load_or_make_centroids(3, small(), dir).outcome, CacheOutcome::kHit);
}

TEST(CentroidCache, ADamagedFileIsRegeneratedWithAWarning) {
  const fs::path dir = fresh_dir("damaged");
  const CachedCentroids made = load_or_make_centroids(3, small(), dir);
  const auto size = fs::file_size(made.path);
  const auto damage = [&](const std::function<void()>& how, const std::string& expected) {
    how();
    const CachedCentroids again = load_or_make_centroids(3, small(), dir);
    EXPECT_EQ(again.outcome, CacheOutcome::kRegenerated);
    EXPECT_NE(again.warning.find(expected), std::string::npos) << again.warning;
    EXPECT_TRUE(again.centroids == made.centroids);
    EXPECT_EQ(load_or_make_centroids(3, small(), dir).outcome, CacheOutcome::kHit);  // rewritten whole
  };
  damage([&] { fs::resize_file(made.path, size - 5); }, "bytes, expected");
  damage(
      [&] {  // one flipped bit in the data
        std::fstream f(made.path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(static_cast<std::streamoff>(size / 2));
        char c = 0;
        f.read(&c, 1);
        f.seekp(static_cast<std::streamoff>(size / 2));
        c = static_cast<char>(c ^ 0x10);
        f.write(&c, 1);
      },
      "checksum");
  damage([&] { std::ofstream(made.path) << "not a cache file\n"; }, "is not a cache file");
}

TEST(CentroidCache, ReadingAFileForAnotherKeyThrows) {
  const fs::path dir = fresh_dir("other");
  const CachedCentroids made = load_or_make_centroids(3, small(), dir);
  EXPECT_THROW(read_centroid_file(made.path, "cvt-other", 20, 3), Error);
  EXPECT_THROW(read_centroid_file(made.path, centroid_cache_key(3, small()), 20, 4), Error);
  EXPECT_TRUE(read_centroid_file(made.path, centroid_cache_key(3, small()), 20, 3) == made.centroids);
}

TEST(CentroidCache, AnEmptyDirectoryDisablesTheCache) {
  const CachedCentroids c = load_or_make_centroids(3, small(), {});
  EXPECT_EQ(c.outcome, CacheOutcome::kDisabled);
  EXPECT_TRUE(c.path.empty());
  EXPECT_EQ(c.centroids.rows(), 20);
}

}  // namespace
}  // namespace qdmeta
