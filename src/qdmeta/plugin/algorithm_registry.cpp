#include "qdmeta/plugin/algorithm_registry.hpp"

#include "qdmeta/plugin/registry.hpp"

namespace qdmeta {
namespace {

Registry<AlgorithmBuilder>& algorithms() {
  static Registry<AlgorithmBuilder> r;
  return r;
}

}  // namespace

void register_algorithm(const std::string& name, AlgorithmBuilder builder) { algorithms().add(name, std::move(builder)); }

std::shared_ptr<const AlgorithmBuilder> find_algorithm(std::string_view name) { return algorithms().find(name); }

std::vector<std::string> registered_algorithm_names() { return algorithms().names(); }

}  // namespace qdmeta
