#pragma once
// What a config's readers need of a task, read from its table without making the task: its name,
// sizes and QD-score offset. A config that is only resolved (an experiment's conditions and kept
// runs, BuildScope::kResolve) hands its readers a Task of this shape, which evaluates nothing.
#include <string>

#include "qdmeta/core/task.hpp"

namespace qdmeta {

struct TaskShape {
  std::string name;
  Index genotype_size = 0;
  Index base_feature_size = 0;
  double qd_offset = 0.0;
  bool operator==(const TaskShape&) const = default;
};

// A task of `shape`: its name, sizes and offset are the shape's; evaluating it is an Error.
Task task_of_shape(TaskShape shape);
TaskShape shape_of(const Task& task);

}  // namespace qdmeta
