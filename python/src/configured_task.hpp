#pragma once
// A built-in task made from its [task] table by qdmeta.Task.builtin(): the task and the
// resolved table it came from, so that it pickles as that table (and an unpickled copy, built
// from it again, is the same task). It models UserTask by passing everything to the task.
#include <string>
#include <utility>

#include <toml++/toml.h>

#include "qdmeta/core/task.hpp"

namespace qdmeta::python {

class ConfiguredTask {
 public:
  ConfiguredTask(Task task, toml::table table) : task_(std::move(task)), table_(std::move(table)) {}
  // A copy is a worker's own copy (Task::clone), so it clones the task too.
  ConfiguredTask(const ConfiguredTask& other) : task_(other.task_.clone()), table_(other.table_) {}
  ConfiguredTask(ConfiguredTask&&) = default;
  ConfiguredTask& operator=(const ConfiguredTask&) = delete;
  ConfiguredTask& operator=(ConfiguredTask&&) = default;
  ~ConfiguredTask() = default;

  std::string name() const { return task_.name(); }
  Index genotype_size() const { return task_.genotype_size(); }
  Index base_feature_size() const { return task_.base_feature_size(); }
  double qd_offset() const { return task_.qd_offset(); }
  bool shareable() const { return task_.shareable(); }
  void evaluate(GenotypeView genotypes, EvaluationView out) const { task_.evaluate(genotypes, out); }

  // The resolved [task] table, every key in force.
  const toml::table& table() const { return table_; }

 private:
  Task task_;
  toml::table table_;
};

// The table a task was made from by Task.builtin(), or null.
inline const toml::table* builtin_table(const Task& task) {
  const auto* configured = task.target<ConfiguredTask>();
  return configured != nullptr ? &configured->table() : nullptr;
}

}  // namespace qdmeta::python
