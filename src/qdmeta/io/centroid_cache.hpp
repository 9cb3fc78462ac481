#pragma once
// CVT centroids cached on disk, keyed by everything that determines them (dimension, count,
// points, seeding, method, iterations, seed), so repeated runs skip k-means. A cache file holds
// a header line with its key, the centroids as little-endian float32 and a checksum; it is
// written atomically. A file that does not read back whole and matching is never used: it is
// regenerated and a warning says why.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "qdmeta/archive/kmeans.hpp"

namespace qdmeta {

enum class CacheOutcome { kDisabled, kHit, kMiss, kRegenerated };
inline constexpr EnumNames<CacheOutcome, 4> kCacheOutcomeNames{{{CacheOutcome::kDisabled, "disabled"},
                                                                 {CacheOutcome::kHit, "hit"},
                                                                 {CacheOutcome::kMiss, "miss"},
                                                                 {CacheOutcome::kRegenerated, "regenerated"}}};

struct CachedCentroids {
  RowMatrix centroids;
  CacheOutcome outcome = CacheOutcome::kDisabled;
  std::filesystem::path path;  // the cache file (empty when disabled)
  std::string warning;         // why a cache file was regenerated
  std::vector<double> cost;    // k-means cost history when k-means ran (empty on a hit)
};

// $XDG_CACHE_HOME/qdmeta/centroids, else $HOME/.cache/qdmeta/centroids, else empty.
std::filesystem::path default_centroid_cache_dir();

// The key, also the file's name without extension: e.g.
// "cvt-d20-k10000-n1000000-init-k-means++100000-lloyd-i10-s1".
std::string centroid_cache_key(Index dimensions, const KMeansParams& params);

// Reads a cache file; throws Error saying what is wrong if it is not a whole file for `key`.
RowMatrix read_centroid_file(const std::filesystem::path& path, const std::string& key, Index count,
                             Index dimensions);
void write_centroid_file(const std::filesystem::path& path, const std::string& key, const RowMatrix& centroids);

// Points for k-means other than params.samples uniform ones (e.g. a task's descriptors):
// `key` names everything that determines them besides `params` (it is appended to the cache
// key, so keep it to file-name characters), `make` draws them (only on a cache miss).
struct CentroidPoints {
  std::string key;
  std::function<RowMatrix()> make;
};

// The centroids from `cache_dir` when there, else k-means (then stored): over `points` when
// given, else over uniform points. An empty cache_dir disables the cache. The directory is
// created when missing. `on_make`, when given, hears one line before k-means starts (it can take
// minutes, so a user should learn why the run seems to stall).
CachedCentroids load_or_make_centroids(Index dimensions, const KMeansParams& params,
                                       const std::filesystem::path& cache_dir, const CentroidPoints* points = nullptr,
                                       const std::function<void(const std::string&)>& on_make = {});

}  // namespace qdmeta
