#pragma once
// The Task interface: a user type that evaluates a batch of genotypes into fitness, base
// features and a valid flag, wrapped once in the value type `Task`, which checks every size,
// range and NaN and names the task in its messages (after pagmo2's problem, with a concept).
#include <concepts>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "qdmeta/core/scalars.hpp"

namespace qdmeta {

// Ends the message for a base feature outside [0, 1], for a user who set [archive] lower and
// upper to the task's own range: the contract is [0, 1] (QD-Meta's networks and the CVT centroids
// are built on it), and those keys bound the archive's axes, the target features.
inline constexpr std::string_view kBaseFeatureRangeHint =
    " (base features are in [0, 1] whatever [archive] lower and upper say: those bound the archive's axes; "
    "scale the task's features into [0, 1])";

// A contiguous, row-major block of genotypes (one per row), each gene in [0, 1].
struct GenotypeView {
  const Real* data = nullptr;
  Index count = 0;
  Index genotype_size = 0;
  Index first_row = 0;  // the batch row of this block's first row: messages name batch rows
  const Real* row(Index i) const { return data + i * genotype_size; }
  GenotypeView rows(Index first, Index n) const { return {row(first), n, genotype_size, first_row + first}; }
};

// Where a task writes its results, in batch order. Base features are row-major (count x size).
struct EvaluationView {
  Real* fitness = nullptr;
  Real* base_features = nullptr;
  std::uint8_t* valid = nullptr;  // 1 = valid; invalid ("dead") solutions never enter an archive
  Index count = 0;
  Index base_feature_size = 0;
  Real* base_row(Index i) const { return base_features + i * base_feature_size; }
  EvaluationView rows(Index first, Index n) const {
    return {fitness + first, base_row(first), valid + first, n, base_feature_size};
  }
};

// What a user's task must provide. Optional members: `std::string name() const`,
// `bool shareable() const` (true: one instance may serve all threads; default false, so each
// worker gets a copy), `double qd_offset() const` (QD-score offset, default 0),
// `static constexpr bool kOwnErrors = true` (its exceptions reach the caller as thrown, with no
// row located: the Python module's tasks, whose exceptions are Python's).
template <class T>
concept UserTask = std::copy_constructible<T> && requires(const T& t, GenotypeView g, EvaluationView e) {
  { t.genotype_size() } -> std::convertible_to<Index>;
  { t.base_feature_size() } -> std::convertible_to<Index>;
  t.evaluate(g, e);
};

class Task {
 public:
  template <UserTask T>
    requires(!std::same_as<std::remove_cvref_t<T>, Task>)
  explicit Task(T user_task) : impl_(std::make_shared<Model<T>>(std::move(user_task))) {
    validate_sizes();
  }

  const std::string& name() const { return impl_->name; }
  Index genotype_size() const { return impl_->genotype_size; }
  Index base_feature_size() const { return impl_->base_feature_size; }
  bool shareable() const { return impl_->shareable; }
  double qd_offset() const { return impl_->qd_offset; }

  // Evaluates a batch, then checks what the task wrote: finite fitness, base features in
  // [0, 1], for every valid row. Throws Error naming the task, the row and the value. An
  // exception of the task's own (not a qdmeta::Error) becomes TaskFailed, naming the row that
  // threw (found by evaluating the block's rows one by one) and nesting the original.
  void evaluate(GenotypeView genotypes, EvaluationView out) const;

  // An independent copy for a worker that may not share this instance.
  Task clone() const { return Task(impl_->clone()); }
  // The wrapped user task if it is a T (like std::function::target), else nullptr.
  template <class T>
  const T* target() const {
    const auto* model = dynamic_cast<const Model<T>*>(impl_.get());
    return model != nullptr ? &model->task : nullptr;
  }
  // Identity of the wrapped instance: copies of a Task share it, clones do not.
  const void* id() const { return impl_.get(); }

 private:
  struct Concept {
    std::string name;
    Index genotype_size = 0;
    Index base_feature_size = 0;
    bool shareable = false;
    double qd_offset = 0.0;
    bool own_errors = false;
    virtual ~Concept() = default;
    virtual void evaluate(GenotypeView, EvaluationView) const = 0;
    virtual std::shared_ptr<Concept> clone() const = 0;
  };
  template <class T>
  struct Model final : Concept {
    T task;
    explicit Model(T t) : task(std::move(t)) {
      if constexpr (requires { { task.name() } -> std::convertible_to<std::string>; }) name = task.name();
      else name = "task";
      genotype_size = static_cast<Index>(task.genotype_size());
      base_feature_size = static_cast<Index>(task.base_feature_size());
      if constexpr (requires { { task.shareable() } -> std::convertible_to<bool>; }) shareable = task.shareable();
      if constexpr (requires { { task.qd_offset() } -> std::convertible_to<double>; }) qd_offset = task.qd_offset();
      if constexpr (requires { { T::kOwnErrors } -> std::convertible_to<bool>; }) own_errors = T::kOwnErrors;
    }
    void evaluate(GenotypeView g, EvaluationView e) const override { task.evaluate(g, e); }
    std::shared_ptr<Concept> clone() const override { return std::make_shared<Model<T>>(task); }
  };
  explicit Task(std::shared_ptr<Concept> impl) : impl_(std::move(impl)) {}
  void validate_sizes() const;
  void evaluate_naming_failures(GenotypeView genotypes, EvaluationView out) const;

  std::shared_ptr<Concept> impl_;
};

}  // namespace qdmeta
