#pragma once
// The evaluator of runs driven from Python: a Python task is called once per batch on the
// calling thread (one numpy call beats many small ones, and calls hold the GIL anyway); C++
// tasks and the algorithms' own parallel work (rebuilds, cell lookups) go to the thread
// evaluator as usual. Results do not depend on the thread count.
#include <memory>
#include <vector>

#include "python_task.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta::python {

class PythonAwareEvaluator final : public Evaluator {
 public:
  explicit PythonAwareEvaluator(int threads) : inner_(make_evaluator(threads)) {}

  void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) override {
    if (is_python_task(task)) task.evaluate(genotypes, out);
    else inner_->evaluate(task, genotypes, out);
  }
  void evaluate_jobs(std::span<const EvaluationJob> jobs) override {
    std::vector<EvaluationJob> native;
    for (const EvaluationJob& j : jobs) {
      if (is_python_task(*j.task)) j.task->evaluate(j.genotypes, j.out);
      else native.push_back(j);
    }
    if (!native.empty()) inner_->evaluate_jobs(native);
  }
  int workers() const override { return inner_->workers(); }
  void parallel_for(Index n, const std::function<void(Index)>& body) override { inner_->parallel_for(n, body); }
  void within_workers(const std::function<void()>& fn) override { inner_->within_workers(fn); }

 private:
  std::unique_ptr<Evaluator> inner_;
};

}  // namespace qdmeta::python
