// The evaluators of src/qdmeta/eval: every one gives the serial evaluator's bits, whatever the
// thread count, chunk size or batch size, for shareable tasks and for tasks that get a copy per
// thread (never one instance on two threads at once); a task's exception reaches the caller as
// itself, and the evaluator serves the next batch as before.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {
namespace {

// Each row's result depends on its genes only: fitness a sum of sines, base features the first two
// genes folded into [0, 1], invalid when gene 0 is above 0.9. `shareable` as asked.
struct SineTask {
  bool share = true;
  bool shareable() const { return share; }
  std::string name() const { return "sine"; }
  Index genotype_size() const { return 5; }
  Index base_feature_size() const { return 2; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    for (Index i = 0; i < g.count; ++i) {
      double f = 0;
      for (Index k = 0; k < g.genotype_size; ++k) f += std::sin(3.0 * (k + 1) * g.row(i)[k]);
      e.fitness[i] = static_cast<Real>(f);
      e.base_row(i)[0] = g.row(i)[1];
      e.base_row(i)[1] = std::abs(g.row(i)[2] - g.row(i)[3]);
      e.valid[i] = g.row(i)[0] <= Real(0.9) ? 1 : 0;
    }
  }
};

RowMatrix genotypes(Index rows, std::uint64_t seed) {
  Rng rng(seed);
  RowMatrix g(rows, 5);
  for (Index r = 0; r < rows; ++r)
    for (Index k = 0; k < 5; ++k) g(r, k) = static_cast<Real>(rng.uniform());
  return g;
}

EvaluationBatch evaluated(Evaluator& evaluator, const Task& task, const RowMatrix& g) {
  EvaluationBatch out;
  out.resize(g.rows(), task.base_feature_size());
  evaluator.evaluate(task, {g.data(), g.rows(), g.cols()}, out.view());
  return out;
}

void expect_same(const EvaluationBatch& a, const EvaluationBatch& b, const std::string& what) {
  EXPECT_EQ(a.fitness, b.fitness) << what;
  EXPECT_TRUE(a.base_features == b.base_features) << what;
  EXPECT_EQ(a.valid, b.valid) << what;
}

struct Setting {
  int threads;
  Index chunk_rows;
  double cheap_batch_seconds;
};

TEST(Evaluators, EveryThreadCountChunkAndBatchSizeGivesTheSerialBits) {
  const Setting settings[] = {{1, 32, 200e-6}, {2, 1, 200e-6}, {2, 7, 200e-6}, {4, 32, 200e-6},
                              {3, 5, 1e9}};  // 1e9: every batch after the first stays on the caller
  for (const bool share : {true, false}) {
    const Task task{SineTask{share}};
    for (const Index rows : {0, 1, 7, 31, 32, 33, 1000}) {
      const RowMatrix g = genotypes(rows, 40 + static_cast<std::uint64_t>(rows));
      SerialEvaluator serial;
      const EvaluationBatch expected = evaluated(serial, task, g);
      if (rows == 1000) {  // the check is not vacuous: both kinds of row are there
        EXPECT_NE(std::count(expected.valid.begin(), expected.valid.end(), 0), 0);
        EXPECT_NE(std::count(expected.valid.begin(), expected.valid.end(), 1), 0);
      }
      for (const Setting& s : settings) {
        const auto evaluator = make_thread_evaluator(s.threads, s.chunk_rows, s.cheap_batch_seconds);
        const std::string what = "shareable " + std::to_string(share) + ", " + std::to_string(rows) + " rows, " +
                                 std::to_string(s.threads) + " threads, chunks of " + std::to_string(s.chunk_rows);
        for (int batch = 0; batch < 3; ++batch) expect_same(evaluated(*evaluator, task, g), expected, what);
      }
    }
  }
}

TEST(Evaluators, JobsOfSeveralTasksGiveEachTasksSerialBits) {
  const Task shared{SineTask{true}}, copied{SineTask{false}};
  const RowMatrix a = genotypes(45, 1), b = genotypes(3, 2), c = genotypes(200, 3);
  SerialEvaluator serial;
  const EvaluationBatch ea = evaluated(serial, shared, a), eb = evaluated(serial, copied, b),
                        ec = evaluated(serial, copied, c);
  for (const int threads : {1, 2, 4}) {
    const auto evaluator = make_thread_evaluator(threads, 8);
    EvaluationBatch oa, ob, oc;
    oa.resize(a.rows(), 2);
    ob.resize(b.rows(), 2);
    oc.resize(c.rows(), 2);
    const EvaluationJob jobs[] = {{&shared, {a.data(), a.rows(), 5}, oa.view()},
                                  {&copied, {b.data(), b.rows(), 5}, ob.view()},
                                  {&copied, {c.data(), c.rows(), 5}, oc.view()}};
    evaluator->evaluate_jobs(jobs);
    expect_same(oa, ea, "job a, threads " + std::to_string(threads));
    expect_same(ob, eb, "job b, threads " + std::to_string(threads));
    expect_same(oc, ec, "job c, threads " + std::to_string(threads));
  }
}

// An unshareable task whose every instance (the original and each copy) counts the threads inside
// it at once; `overlapped` is set if it ever saw two.
struct SingleThreadedTask {
  std::shared_ptr<std::atomic<int>> inside = std::make_shared<std::atomic<int>>(0);
  std::shared_ptr<std::atomic<bool>> overlapped = std::make_shared<std::atomic<bool>>(false);
  SingleThreadedTask() = default;
  SingleThreadedTask(const SingleThreadedTask& other)  // a copy is a new instance: its own count
      : inside(std::make_shared<std::atomic<int>>(0)), overlapped(other.overlapped) {}
  SingleThreadedTask& operator=(const SingleThreadedTask&) = delete;
  Index genotype_size() const { return 1; }
  Index base_feature_size() const { return 0; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    if (++*inside > 1) *overlapped = true;
    std::this_thread::sleep_for(std::chrono::microseconds(200));  // long enough for a second thread to come in
    for (Index i = 0; i < g.count; ++i) {
      e.fitness[i] = g.row(i)[0];
      e.valid[i] = 1;
    }
    --*inside;
  }
};

TEST(Evaluators, AnUnshareableTaskIsNeverOnTwoThreadsAtOnce) {
  const SingleThreadedTask user;
  const Task task{user};
  ASSERT_FALSE(task.shareable());
  RowMatrix g(64, 1);
  for (Index r = 0; r < 64; ++r) g(r, 0) = static_cast<Real>(r) / 64;
  const auto evaluator = make_thread_evaluator(4, 1, 0.0);
  for (int batch = 0; batch < 3; ++batch) {
    EvaluationBatch out;
    out.resize(64, 0);
    evaluator->evaluate(task, {g.data(), 64, 1}, out.view());
    for (Index r = 0; r < 64; ++r) ASSERT_EQ(out.fitness[r], g(r, 0));
    EvaluationBatch job_out;
    job_out.resize(64, 0);
    const EvaluationJob jobs[] = {{&task, {g.data(), 32, 1}, job_out.view().rows(0, 32)},
                                  {&task, {g.row(32).data(), 32, 1}, job_out.view().rows(32, 32)}};
    evaluator->evaluate_jobs(jobs);
    EXPECT_EQ(job_out.fitness, out.fitness);
  }
  EXPECT_FALSE(*user.overlapped);
}

// Throws at genes in [0.5, 0.6): an InputError, as a task reading a bad file would.
struct FailingTask {
  bool shareable() const { return true; }
  Index genotype_size() const { return 1; }
  Index base_feature_size() const { return 0; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    for (Index i = 0; i < g.count; ++i) {
      if (g.row(i)[0] >= Real(0.5) && g.row(i)[0] < Real(0.6)) throw InputError("failing task: a gene in [0.5, 0.6)");
      e.fitness[i] = 1;
      e.valid[i] = 1;
    }
  }
};

// Writes NaN fitness for a valid row: the Task wrapper's check refuses it.
struct NanTask {
  bool shareable() const { return true; }
  std::string name() const { return "nan-task"; }
  Index genotype_size() const { return 1; }
  Index base_feature_size() const { return 0; }
  void evaluate(GenotypeView g, EvaluationView e) const {
    for (Index i = 0; i < g.count; ++i) {
      e.fitness[i] = g.row(i)[0] > Real(0.7) ? std::nanf("") : Real(1);
      e.valid[i] = 1;
    }
  }
};

TEST(Evaluators, ATasksErrorReachesTheCallerAndTheEvaluatorGoesOn) {
  RowMatrix g(100, 1);
  for (Index r = 0; r < 100; ++r) g(r, 0) = static_cast<Real>(r) / 100;
  const Task failing{FailingTask{}}, nan{NanTask{}}, good{SineTask{true}};
  const RowMatrix good_genes = genotypes(100, 9);
  SerialEvaluator serial;
  const EvaluationBatch expected = evaluated(serial, good, good_genes);
  std::vector<std::unique_ptr<Evaluator>> evaluators;
  evaluators.push_back(std::make_unique<SerialEvaluator>());
  for (const int threads : {1, 2, 4}) evaluators.push_back(make_thread_evaluator(threads, 8, 0.0));
  for (auto& evaluator : evaluators) {
    const std::string what = std::to_string(evaluator->workers()) + " workers";
    EvaluationBatch out;
    out.resize(100, 0);
    try {
      evaluator->evaluate(failing, {g.data(), 100, 1}, out.view());
      ADD_FAILURE() << what << ": no error";
    } catch (const InputError& e) {
      EXPECT_STREQ(e.what(), "failing task: a gene in [0.5, 0.6)") << what;
    }
    try {
      evaluator->evaluate(nan, {g.data(), 100, 1}, out.view());
      ADD_FAILURE() << what << ": no error";
    } catch (const InputError&) {
      ADD_FAILURE() << what << ": a task's bad output is the program's error, not the input's";
    } catch (const Error& e) {
      EXPECT_TRUE(std::string(e.what()).starts_with("task 'nan-task': fitness of solution ")) << e.what();
    }
    const EvaluationJob jobs[] = {{&failing, {g.data(), 100, 1}, out.view()}};
    EXPECT_THROW(evaluator->evaluate_jobs(jobs), InputError) << what;
    expect_same(evaluated(*evaluator, good, good_genes), expected, what + ", after the errors");
  }
}

}  // namespace
}  // namespace qdmeta
