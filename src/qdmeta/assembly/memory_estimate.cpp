#include "qdmeta/assembly/memory_estimate.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

std::optional<MemoryLimit> memory_limit() {
  std::optional<MemoryLimit> best;
  const auto consider = [&](double bytes, const char* source) {
    if (bytes > 0 && (!best || bytes < best->bytes)) best = MemoryLimit{bytes, source};
  };
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) consider(static_cast<double>(pages) * static_cast<double>(page), "physical memory");
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) consider(static_cast<double>(as.rlim_cur), "ulimit -v");
  std::ifstream cgroup("/sys/fs/cgroup/memory.max");  // cgroup v2; "max" when unlimited
  if (std::string text; cgroup >> text && text != "max") {
    try {
      consider(std::stod(text), "cgroup memory.max");
    } catch (const std::exception&) {
    }
  }
  return best;
}

std::string format_bytes(double bytes) {
  if (bytes >= 1024.0 * 1024 * 1024 * 1024) return fmt::format("{:.1f} TiB", bytes / (1024.0 * 1024 * 1024 * 1024));
  if (bytes >= 1024.0 * 1024 * 1024) return fmt::format("{:.2f} GiB", bytes / (1024.0 * 1024 * 1024));
  if (bytes >= 1024.0 * 1024) return fmt::format("{:.0f} MiB", bytes / (1024.0 * 1024));
  return fmt::format("{:.1f} KiB", bytes / 1024.0);
}

void require_memory(const MemoryEstimate& estimate, const std::optional<MemoryLimit>& limit, const std::string& source) {
  if (!limit || estimate.total() <= limit->bytes) return;
  std::vector<MemoryTerm> terms = estimate.terms;
  std::sort(terms.begin(), terms.end(), [](const MemoryTerm& a, const MemoryTerm& b) { return a.bytes > b.bytes; });
  std::string largest;
  for (std::size_t i = 0; i < std::min<std::size_t>(2, terms.size()); ++i)
    largest += fmt::format("{}{} for {} ({})", i ? "; " : "", format_bytes(terms[i].bytes), terms[i].what, terms[i].keys);
  throw InputError(fmt::format("{}: this run needs at least {} of memory but {} allows {}: {}; lower those keys", source,
                               format_bytes(estimate.total()), limit->source, format_bytes(limit->bytes), largest));
}

}  // namespace qdmeta
