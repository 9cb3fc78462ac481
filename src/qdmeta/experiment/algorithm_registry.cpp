#include "qdmeta/experiment/algorithm_registry.hpp"

#include <algorithm>
#include <mutex>
#include <utility>

#include "qdmeta/experiment/config.hpp"
#include "qdmeta/experiment/core_plugins.hpp"
#include "qdmeta/experiment/memory_estimate.hpp"

namespace qdmeta {
namespace {

struct Registry {
  std::mutex mutex;
  // Registration order is the order the CLI and docs/config.md list them in; shared snapshots
  // keep a found builder valid while others are added or it is replaced.
  std::vector<std::pair<std::string, std::shared_ptr<const AlgorithmBuilder>>> builders;
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void AlgorithmBuild::check_memory() const {
  if (make) require_memory(built.memory, memory_limit(), root.source());
}

void register_algorithm(const std::string& name, AlgorithmBuilder builder) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  auto owned = std::make_shared<const AlgorithmBuilder>(std::move(builder));
  const auto same = std::find_if(r.builders.begin(), r.builders.end(), [&](const auto& b) { return b.first == name; });
  if (same != r.builders.end()) same->second = std::move(owned);
  else r.builders.emplace_back(name, std::move(owned));
}

std::shared_ptr<const AlgorithmBuilder> find_algorithm(std::string_view name) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  for (const auto& [n, builder] : r.builders)
    if (n == name) return builder;
  return nullptr;
}

std::vector<std::string> registered_algorithm_names() {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [n, builder] : r.builders) names.push_back(n);
  return names;
}

}  // namespace qdmeta
