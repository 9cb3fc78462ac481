#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <optional>
#include <vector>

#include "qdmeta/core/parallel.hpp"
#include "qdmeta/core/seconds_since.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {
namespace {

class ThreadEvaluator final : public Evaluator {
 public:
  ThreadEvaluator(int threads, Index chunk_rows, double cheap_batch_seconds)
      : threads_(threads > 0 ? threads : tbb::info::default_concurrency()),
        chunk_rows_(chunk_rows > 0 ? chunk_rows : 32),
        cheap_batch_seconds_(cheap_batch_seconds),
        arena_(threads_) {}

  void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) override {
    const Index chunks = (genotypes.count + chunk_rows_ - 1) / chunk_rows_;
    // A batch that takes a few tens of microseconds (400 Rastrigin rows) costs more to hand to
    // the other threads than it saves: once a batch of this task ran that fast, the next ones
    // run here, until one of them is slow. Only the timing changes, never a result (each row's
    // result does not depend on the split).
    const bool cheap = cheap_task_ == task.id();
    const auto start = std::chrono::steady_clock::now();
    if (chunks <= 1 || threads_ == 1 || cheap) {
      task.evaluate(genotypes, out);
      if (cheap && seconds_since(start) > 2 * cheap_batch_seconds_) cheap_task_ = nullptr;
      return;
    }
    // Per-thread copies of a task that may not be shared (e.g. a physics world), kept
    // across batches while the same task is evaluated.
    if (copies_of_ != task.id()) {
      copies_.clear();
      copies_of_ = task.id();
    }
    arena_.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<Index>(0, chunks, 1),
          [&](const tbb::blocked_range<Index>& range) {
            const Task* worker_task = &task;
            if (!task.shareable()) {
              auto& copy = copies_.local();
              if (!copy) copy.emplace(task.clone());
              worker_task = &*copy;
            }
            for (Index c = range.begin(); c < range.end(); ++c) {
              const Index first = c * chunk_rows_;
              const Index n = std::min(chunk_rows_, genotypes.count - first);
              worker_task->evaluate(genotypes.rows(first, n), out.rows(first, n));
            }
          },
          tbb::simple_partitioner());
    });
    if (seconds_since(start) < cheap_batch_seconds_) cheap_task_ = task.id();
  }
  // All jobs' chunks in one pool, so a request of many small batches (a meta-fitness's
  // environments) keeps every thread busy. Copies of unshareable tasks live for this call.
  void evaluate_jobs(std::span<const EvaluationJob> jobs) override {
    struct Piece {
      std::size_t job;
      Index first, rows;
    };
    std::vector<Piece> pieces;
    for (std::size_t j = 0; j < jobs.size(); ++j)
      for (Index first = 0; first < jobs[j].genotypes.count; first += chunk_rows_)
        pieces.push_back({j, first, std::min(chunk_rows_, jobs[j].genotypes.count - first)});
    if (pieces.size() <= 1 || threads_ == 1) {
      Evaluator::evaluate_jobs(jobs);
      return;
    }
    tbb::enumerable_thread_specific<std::vector<std::optional<Task>>> copies(
        [&] { return std::vector<std::optional<Task>>(jobs.size()); });
    arena_.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, pieces.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& range) {
            auto& local = copies.local();
            for (std::size_t i = range.begin(); i < range.end(); ++i) {
              const Piece& p = pieces[i];
              const EvaluationJob& job = jobs[p.job];
              const Task* task = job.task;
              if (!task->shareable()) {
                if (!local[p.job]) local[p.job].emplace(task->clone());
                task = &*local[p.job];
              }
              task->evaluate(job.genotypes.rows(p.first, p.rows), job.out.rows(p.first, p.rows));
            }
          },
          tbb::simple_partitioner());
    });
  }
  int workers() const override { return threads_; }

  void parallel_for(Index n, const std::function<void(Index)>& body) override {
    arena_.execute([&] { parallel_indices(n, body); });
  }
  void within_workers(const std::function<void()>& fn) override { arena_.execute(fn); }

 private:
  int threads_;
  Index chunk_rows_;
  double cheap_batch_seconds_;
  const void* cheap_task_ = nullptr;  // the task whose batches run on the calling thread
  tbb::task_arena arena_;
  tbb::enumerable_thread_specific<std::optional<Task>> copies_;
  const void* copies_of_ = nullptr;
};

}  // namespace

void SerialEvaluator::within_workers(const std::function<void()>& fn) {
  tbb::task_arena one(1);
  one.execute(fn);
}

std::unique_ptr<Evaluator> make_thread_evaluator(int threads, Index chunk_rows, double cheap_batch_seconds) {
  return std::make_unique<ThreadEvaluator>(threads, chunk_rows, cheap_batch_seconds);
}

std::unique_ptr<Evaluator> make_evaluator(int threads) {
  if (threads == 1) return std::make_unique<SerialEvaluator>();
  return make_thread_evaluator(threads);
}

}  // namespace qdmeta
