#pragma once
// CVT-MAP-Elites's centroids as a run makes them: read from the centroid cache when there, else
// k-means over uniform points or over the task's random descriptors, then cached. The algorithm
// takes them as a value through its CentroidSource and reads no file itself.
#include <filesystem>
#include <string>

#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/archive/kmeans.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta {

// Where k-means takes its points: uniform in [0,1]^d, or the base features of feasible random
// genotypes of the task (docs/specification.md, CVT-MAP-Elites, for RHex).
enum class CvtPoints { kUniform, kRandomDescriptors };
inline constexpr EnumNames<CvtPoints, 2> kCvtPointsNames{
    {{CvtPoints::kUniform, "uniform"}, {CvtPoints::kRandomDescriptors, "random-descriptors"}}};

struct CvtCentroidSettings {
  std::filesystem::path cache_dir;         // centroid cache directory; empty: no cache
  CvtPoints points = CvtPoints::kUniform;  // k-means over kmeans.samples points of this kind
  Index max_attempts = 0;  // random-descriptors: give up after this many genotypes (0: 10 x samples)
  // random-descriptors: names the task settings that determine its descriptors, in the cache key
  // (the builder uses a hash of the resolved [task] table); empty: the task's name only.
  std::string task_key;
};

// The source that makes `kmeans`'s centroids for `task` as `settings` say, announcing k-means
// (it can take minutes) and a regenerated cache file as notices.
CentroidSource cvt_centroid_source(CvtCentroidSettings settings, KMeansParams kmeans, Task task);

}  // namespace qdmeta
