#pragma once
// Algorithms, found by the name that the config's `algorithm` key selects: the four built-in
// ones (assembly/builtin_algorithms.hpp) and any a program registers, all through
// register_algorithm() into one Registry (plugin/registry.hpp). A caller may instead hand a
// builder to build_run() as a part (run_parts.hpp), registering nothing.
// The builder protocol that build_run() runs around each: algorithm_builder.hpp.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/plugin/algorithm_builder.hpp"

namespace qdmeta {

// Registers (or replaces) the builder for `name`. Thread-safe. The config's default is
// "map-elites" where registered, else the first name registered.
void register_algorithm(const std::string& name, AlgorithmBuilder builder);
// The builder registered under `name`, or nullptr: a snapshot, which later registrations (of this
// name too) leave unchanged.
std::shared_ptr<const AlgorithmBuilder> find_algorithm(std::string_view name);
// Registered names in registration order.
std::vector<std::string> registered_algorithm_names();

}  // namespace qdmeta
