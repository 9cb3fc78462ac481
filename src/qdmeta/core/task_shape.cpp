#include "qdmeta/core/task_shape.hpp"

#include <fmt/format.h>

#include <utility>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

struct ShapeOnlyTask {
  TaskShape shape;
  std::string name() const { return shape.name; }
  Index genotype_size() const { return shape.genotype_size; }
  Index base_feature_size() const { return shape.base_feature_size; }
  double qd_offset() const { return shape.qd_offset; }
  bool shareable() const { return true; }
  void evaluate(GenotypeView, EvaluationView) const {
    throw Error(fmt::format("task '{}' was only resolved from its config, not made: it evaluates nothing", shape.name));
  }
};

}  // namespace

Task task_of_shape(TaskShape shape) { return Task(ShapeOnlyTask{std::move(shape)}); }

TaskShape shape_of(const Task& task) {
  return {task.name(), task.genotype_size(), task.base_feature_size(), task.qd_offset()};
}

}  // namespace qdmeta
