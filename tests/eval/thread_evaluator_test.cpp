#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {
namespace {

// A shareable task that records which threads evaluated its chunks; each call may sleep, to be
// an expensive task. fitness = 2 x first gene.
struct ThreadRecordingTask {
  struct Log {
    std::mutex mutex;
    std::set<std::thread::id> threads;
  };
  std::shared_ptr<Log> log = std::make_shared<Log>();
  std::chrono::microseconds sleep{0};
  bool shareable() const { return true; }
  Index genotype_size() const { return 1; }
  Index base_feature_size() const { return 1; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    if (sleep.count() > 0) std::this_thread::sleep_for(sleep);
    {
      const std::lock_guard<std::mutex> lock(log->mutex);
      log->threads.insert(std::this_thread::get_id());
    }
    for (Index i = 0; i < g.count; ++i) {
      e.fitness[i] = 2 * g.row(i)[0];
      e.base_row(i)[0] = g.row(i)[0];
      e.valid[i] = 1;
    }
  }
};

RowMatrix ramp(Index rows) {
  RowMatrix g(rows, 1);
  for (Index r = 0; r < rows; ++r) g(r, 0) = static_cast<Real>(r) / static_cast<Real>(rows);
  return g;
}

// With a threshold no batch misses (1 s), the first batch goes to the threads and every later
// one runs on the calling thread alone, with the same results. (Chunks of 100 us, so that
// without the rule the other worker would take some.)
TEST(ThreadEvaluator, BatchesOfACheapTaskStayOnTheCallingThread) {
  ThreadRecordingTask user;
  user.sleep = std::chrono::microseconds(100);
  const Task task{user};
  const auto evaluator = make_thread_evaluator(2, 8, 1.0);
  const RowMatrix g = ramp(400);
  EvaluationBatch out;
  out.resize(400, 1);
  evaluator->evaluate(task, {g.data(), 400, 1}, out.view());
  user.log->threads.clear();
  for (int batch = 0; batch < 5; ++batch) evaluator->evaluate(task, {g.data(), 400, 1}, out.view());
  EXPECT_EQ(user.log->threads, (std::set<std::thread::id>{std::this_thread::get_id()}));
  for (Index r = 0; r < 400; ++r) ASSERT_EQ(out.fitness[r], 2 * g(r, 0)) << r;
}

// An expensive task (2 ms per chunk of 8 rows, 50 chunks a batch) keeps its batches on the
// threads at the default threshold: the other worker takes part.
TEST(ThreadEvaluator, BatchesOfAnExpensiveTaskAreShared) {
  ThreadRecordingTask user;
  user.sleep = std::chrono::microseconds(2000);
  const Task task{user};
  const auto evaluator = make_thread_evaluator(2, 8);
  const RowMatrix g = ramp(400);
  EvaluationBatch out;
  out.resize(400, 1);
  for (int batch = 0; batch < 3; ++batch) evaluator->evaluate(task, {g.data(), 400, 1}, out.view());
  EXPECT_EQ(user.log->threads.size(), 2u);
  for (Index r = 0; r < 400; ++r) ASSERT_EQ(out.fitness[r], 2 * g(r, 0)) << r;
}

// A task that throws its own exception on the row whose gene is 0.5 names that row of the whole
// batch, though each worker saw a chunk of 8 rows (and counted from 0 within it).
TEST(ThreadEvaluator, ATasksExceptionNamesTheRowOfTheWholeBatch) {
  struct ThrowsOnHalf {
    std::string name() const { return "diverges"; }
    Index genotype_size() const { return 1; }
    Index base_feature_size() const { return 1; }
    void evaluate(GenotypeView g, EvaluationView e) const {
      for (Index i = 0; i < g.count; ++i) {
        if (g.row(i)[0] == 0.5f) throw std::runtime_error("simulator diverged");
        e.fitness[i] = 0;
        e.base_row(i)[0] = g.row(i)[0];
        e.valid[i] = 1;
      }
    }
  };
  const Task task{ThrowsOnHalf{}};
  RowMatrix g(40, 1);
  g.setConstant(0.25f);
  g(37, 0) = 0.5f;
  EvaluationBatch out;
  out.resize(40, 1);
  for (const int threads : {1, 2}) {
    const auto evaluator = make_thread_evaluator(threads, 8);
    try {
      evaluator->evaluate(task, {g.data(), 40, 1}, out.view());
      FAIL() << "no exception with " << threads << " threads";
    } catch (const TaskFailed& e) {
      EXPECT_STREQ(e.what(), "task 'diverges' threw on row 37 of the batch: simulator diverged") << threads;
    }
    const EvaluationJob job{&task, {g.data(), 40, 1}, out.view()};
    try {
      evaluator->evaluate_jobs({&job, 1});
      FAIL() << "no exception from evaluate_jobs with " << threads << " threads";
    } catch (const TaskFailed& e) {
      EXPECT_EQ(e.row(), 37) << threads;
    }
  }
}

}  // namespace
}  // namespace qdmeta
