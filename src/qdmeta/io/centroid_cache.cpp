#include "qdmeta/io/centroid_cache.hpp"

#include <fmt/format.h>
#include <fmt/std.h>

#include <bit>
#include <cstdlib>
#include <cstring>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/regular_file.hpp"

namespace qdmeta {
namespace {

static_assert(std::endian::native == std::endian::little, "centroid cache files are little-endian");

constexpr std::string_view kMagic = "qdmeta-centroids 1";

// FNV-1a, 64 bits: enough to tell a truncated or damaged file from a whole one.
std::uint64_t checksum(std::string_view bytes) { return fnv1a64(bytes); }

std::string header(const std::string& key, Index count, Index dimensions) {
  return fmt::format("{} {} {} {}\n", kMagic, key, count, dimensions);
}

}  // namespace

std::filesystem::path default_centroid_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "qdmeta" / "centroids";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "qdmeta" / "centroids";
  return {};
}

std::string centroid_cache_key(Index dimensions, const KMeansParams& p) {
  std::string key = fmt::format("cvt-d{}-k{}-n{}-init-{}", dimensions, p.centroids, p.samples,
                                enum_to_string(kKMeansInitNames, p.init));
  if (p.init == KMeansInit::kPlusPlus) key += fmt::format("{}", std::min(p.init_samples, p.samples));
  key += fmt::format("-{}-i{}", enum_to_string(kKMeansMethodNames, p.method), p.iterations);
  if (p.method == KMeansMethod::kMiniBatch) key += fmt::format("-b{}", p.batch_size);
  return key + fmt::format("-s{}", p.seed);
}

RowMatrix read_centroid_file(const std::filesystem::path& path, const std::string& key, Index count,
                             Index dimensions) {
  const std::string bytes = read_regular_file(path, kMaxBinaryFileBytes);
  const std::string head = header(key, count, dimensions);
  const auto data_size = static_cast<std::size_t>(count * dimensions) * sizeof(Real);
  if (bytes.compare(0, head.size(), head) != 0)
    throw Error(fmt::format("{} is not a cache file for {} ({} x {})", path, key, count, dimensions));
  if (bytes.size() != head.size() + data_size + sizeof(std::uint64_t))
    throw Error(fmt::format("{} has {} bytes, expected {}", path, bytes.size(), head.size() + data_size + 8));
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + head.size() + data_size, sizeof stored);
  if (stored != checksum(std::string_view(bytes).substr(0, head.size() + data_size)))
    throw Error(fmt::format("{} fails its checksum", path));
  RowMatrix centroids(count, dimensions);
  std::memcpy(centroids.data(), bytes.data() + head.size(), data_size);
  if (!centroids.allFinite()) throw Error(fmt::format("{} holds a NaN or infinite coordinate", path));
  return centroids;
}

void write_centroid_file(const std::filesystem::path& path, const std::string& key, const RowMatrix& centroids) {
  std::string bytes = header(key, centroids.rows(), centroids.cols());
  bytes.append(reinterpret_cast<const char*>(centroids.data()), static_cast<std::size_t>(centroids.size()) * sizeof(Real));
  const std::uint64_t sum = checksum(bytes);
  bytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  write_file_atomic(path, bytes);
}

CachedCentroids load_or_make_centroids(Index dimensions, const KMeansParams& params,
                                       const std::filesystem::path& cache_dir, const CentroidPoints* points,
                                       const std::function<void(const std::string&)>& on_make) {
  params.validate();
  CachedCentroids out;
  const std::string key = centroid_cache_key(dimensions, params) + (points ? "-" + points->key : std::string());
  if (!cache_dir.empty()) {
    out.path = cache_dir / (key + ".bin");
    out.outcome = CacheOutcome::kMiss;
    if (path_taken(out.path)) {
      try {
        out.centroids = read_centroid_file(out.path, key, params.centroids, dimensions);
        out.outcome = CacheOutcome::kHit;
        return out;
      } catch (const Error& e) {
        out.outcome = CacheOutcome::kRegenerated;
        out.warning = fmt::format("centroid cache: {}; regenerating it", e.what());
      }
    }
  }
  if (on_make)
    on_make(fmt::format("making {} CVT centroids in {} dimensions by k-means over {} {}points ({}); they are then cached{}",
                        params.centroids, dimensions, params.samples, points ? "task " : "uniform ",
                        cache_dir.empty() ? "cache off"
                                          : out.outcome == CacheOutcome::kRegenerated ? "the cached file was unusable"
                                                                                      : "no cache for these settings",
                        cache_dir.empty() ? " only in memory" : " in " + out.path.string()));
  KMeansResult made;
  if (points) {
    const RowMatrix drawn = points->make();
    if (drawn.cols() != dimensions || drawn.rows() < params.centroids)
      throw Error(fmt::format("centroid points {}: {} x {} given, need at least {} rows of {}", points->key, drawn.rows(),
                              drawn.cols(), params.centroids, dimensions));
    made = kmeans(drawn, params);
  } else {
    made = cvt_centroids(dimensions, params);
  }
  out.centroids = std::move(made.centroids);
  out.cost = std::move(made.cost);
  if (!cache_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(cache_dir, ec);
    if (ec) throw Error(fmt::format("cannot create the centroid cache directory {}: {}", cache_dir, ec.message()));
    write_centroid_file(out.path, key, out.centroids);
  }
  return out;
}

}  // namespace qdmeta
