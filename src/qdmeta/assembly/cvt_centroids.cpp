#include "qdmeta/assembly/cvt_centroids.hpp"

#include <fmt/format.h>

#include <utility>

#include "qdmeta/algorithms/descriptor_points.hpp"
#include "qdmeta/core/notice.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/io/centroid_cache.hpp"

namespace qdmeta {

CentroidSource cvt_centroid_source(CvtCentroidSettings settings, KMeansParams kmeans, Task task) {
  return [settings = std::move(settings), kmeans, task = std::move(task)](Evaluator* workers) {
    SerialEvaluator serial;  // no workers given: the calling thread, the same bits
    Evaluator& evaluator = workers != nullptr ? *workers : serial;
    // k-means on a cache miss can take minutes (about 140 CPU-seconds with the paper's settings).
    const auto announce = [](const std::string& line) {
      notice(NoticeKind::kInformation, fmt::format("{}: this can take minutes", line));
    };
    CachedCentroids made;
    if (settings.points == CvtPoints::kUniform) {
      evaluator.within_workers([&] {
        made = load_or_make_centroids(task.base_feature_size(), kmeans, settings.cache_dir, nullptr, announce);
      });
    } else {
      // Drawn only on a cache miss; the attempts say how many random genotypes were not valid.
      const Index samples = kmeans.samples;
      const Index max_attempts = settings.max_attempts > 0 ? settings.max_attempts : 10 * samples;
      const std::string task_key = settings.task_key.empty() ? task.name() : settings.task_key;
      const CentroidPoints points{fmt::format("desc-{}", task_key), [&] {
                                    const DescriptorPoints d =
                                        feasible_random_descriptors(task, samples, kmeans.seed, evaluator, max_attempts);
                                    notice(NoticeKind::kInformation,
                                           fmt::format("CVT points: {} valid of {} random genotypes ({:.2f}% invalid)",
                                                       samples, d.attempts,
                                                       100.0 * static_cast<double>(d.attempts - samples) /
                                                           static_cast<double>(d.attempts)));
                                    return d.points;
                                  }};
      evaluator.within_workers([&] {
        made = load_or_make_centroids(task.base_feature_size(), kmeans, settings.cache_dir, &points, announce);
      });
    }
    if (!made.warning.empty()) notice(NoticeKind::kWarning, made.warning);
    return std::move(made.centroids);
  };
}

}  // namespace qdmeta
