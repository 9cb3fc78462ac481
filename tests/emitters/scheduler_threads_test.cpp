// Tests of the Scheduler on several threads (emitters/scheduler.hpp): emitters that
// tells_alone() are told at once, with the bits of the in-order loop at any thread count and the
// error of the lowest emitter that threw; any other emitter is told in order on the calling
// thread. Emitters with streams of their own (asks_alone()) are asked at once, to the same bits.
#include <gtest/gtest.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "qdmeta/emitters/scheduler.hpp"
#include "sphere_problem.hpp"

namespace qdmeta {
namespace {

using test::checkpoint_bytes;
using test::kSphereGenes;
using test::sphere_grid;
using test::sphere_step;

constexpr int kToldEmitters = 8;

// Forwards to an emitter and says whether it tells alone as told (false: the in-order loop);
// records on which thread each tell ran, and may throw `error` after a tell (after `delay`).
class ToldWrapper final : public Emitter {
 public:
  ToldWrapper(std::unique_ptr<Emitter> inner, bool alone, std::vector<std::thread::id>* tell_threads = nullptr,
          std::vector<int>* tell_order = nullptr, int index = 0)
      : inner_(std::move(inner)), alone_(alone), tell_threads_(tell_threads), tell_order_(tell_order), index_(index) {}
  Index batch_size() const override { return inner_->batch_size(); }
  Index solution_size() const override { return inner_->solution_size(); }
  const RowMatrix& ask(Rng& rng) override { return inner_->ask(rng); }
  void tell(const EmitterResults& results) override {
    inner_->tell(results);
    if (tell_threads_) tell_threads_->push_back(std::this_thread::get_id());
    if (tell_order_) tell_order_->push_back(index_);
    if (!error.empty()) {
      std::this_thread::sleep_for(delay);
      throw std::runtime_error(error);
    }
  }
  bool tells_alone() const override { return alone_; }
  void save(BinaryWriter& out) const override { inner_->save(out); }
  void load(BinaryReader& in) override { inner_->load(in); }

  std::string error;
  std::chrono::milliseconds delay{0};

 private:
  std::unique_ptr<Emitter> inner_;
  bool alone_;
  std::vector<std::thread::id>* tell_threads_;
  std::vector<int>* tell_order_;
  int index_;
};

EvolutionStrategyEmitterParams told_emitter_params() {
  EvolutionStrategyEmitterParams p;
  p.x0.assign(kSphereGenes, 0.0);
  p.sigma0 = 0.5;
  p.batch_size = 12;
  p.restart = EmitterRestart::kNoImprovement;
  return p;
}

// The archive and scheduler bytes after `iterations` rounds in an arena of `threads`, each
// evolution-strategy emitter wrapped by `wrap`.
template <class Wrap>
std::string bytes_after_rounds(int threads, Wrap wrap, int iterations = 60) {
  GridArchive archive(sphere_grid());
  std::vector<std::unique_ptr<Emitter>> emitters;
  for (auto& e : make_evolution_strategy_emitters(archive, told_emitter_params(), kToldEmitters))
    emitters.push_back(wrap(std::move(e)));
  Scheduler scheduler(archive, ThresholdParams{0.01, 0.0}, std::move(emitters));
  Rng rng(7);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (int i = 0; i < iterations; ++i) sphere_step(scheduler, rng);
  });
  return checkpoint_bytes(archive, scheduler);
}

// The emitters wrapped as telling alone or not.
std::string told_run_bytes(int threads, bool alone, int iterations = 60) {
  return bytes_after_rounds(
      threads, [alone](std::unique_ptr<Emitter> e) { return std::make_unique<ToldWrapper>(std::move(e), alone); },
      iterations);
}

TEST(SchedulerThreads, EmittersToldAtOnceGiveTheInOrderBitsAtAnyThreadCount) {
  const std::string in_order = told_run_bytes(1, false);
  EXPECT_EQ(told_run_bytes(1, true), in_order);
  EXPECT_EQ(told_run_bytes(2, true), in_order);
  EXPECT_EQ(told_run_bytes(std::max(2, tbb::info::default_concurrency()), true), in_order);
  // The run did something: more rounds, other bytes.
  EXPECT_NE(told_run_bytes(1, false, 61), in_order);
}

// An emitter of the Python module's kind: asked with a stream of its own (the scheduler's
// ignored), and saying that it asks alone as told.
class OwnStream final : public Emitter {
 public:
  OwnStream(std::unique_ptr<Emitter> inner, std::uint64_t seed, bool alone)
      : inner_(std::move(inner)), rng_(seed), alone_(alone) {}
  Index batch_size() const override { return inner_->batch_size(); }
  Index solution_size() const override { return inner_->solution_size(); }
  const RowMatrix& ask(Rng& /*scheduler's*/) override { return inner_->ask(rng_); }
  void tell(const EmitterResults& results) override { inner_->tell(results); }
  bool tells_alone() const override { return alone_; }
  bool asks_alone() const override { return alone_; }
  void save(BinaryWriter& out) const override {
    inner_->save(out);
    for (std::uint64_t word : rng_.state().words) out.value(word);
  }
  void load(BinaryReader& /*in*/) override {}

 private:
  std::unique_ptr<Emitter> inner_;
  Rng rng_;
  bool alone_;
};

std::string own_stream_run_bytes(int threads, bool alone) {
  std::uint64_t seed = 100;
  return bytes_after_rounds(threads, [&seed, alone](std::unique_ptr<Emitter> e) {
    return std::make_unique<OwnStream>(std::move(e), seed++, alone);
  });
}

TEST(SchedulerThreads, EmittersAskedAtOnceFromTheirOwnStreamsGiveTheInOrderBits) {
  const std::string in_order = own_stream_run_bytes(1, false);
  EXPECT_EQ(own_stream_run_bytes(1, true), in_order);
  EXPECT_EQ(own_stream_run_bytes(2, true), in_order);
  EXPECT_EQ(own_stream_run_bytes(std::max(2, tbb::info::default_concurrency()), true), in_order);
}

TEST(SchedulerThreads, EvolutionStrategyAndVariationEmittersTellAlone) {
  GridArchive archive(sphere_grid());
  EXPECT_TRUE(EvolutionStrategyEmitter(told_emitter_params(), elite_picker(archive)).tells_alone());
  GaussianEmitterParams gaussian;
  gaussian.x0.assign(kSphereGenes, 0.0);
  EXPECT_TRUE(GaussianEmitter(gaussian, elite_picker(archive)).tells_alone());
  // They draw from the stream they are given, so a scheduler asks them in order.
  EXPECT_FALSE(EvolutionStrategyEmitter(told_emitter_params(), elite_picker(archive)).asks_alone());
}

// Runs one round whose emitters 2 and 5 throw, 2 after a delay (so that 5 throws first in time).
std::string error_of_a_round(bool alone) {
  GridArchive archive(sphere_grid());
  std::vector<std::unique_ptr<Emitter>> emitters;
  for (auto& e : make_evolution_strategy_emitters(archive, told_emitter_params(), kToldEmitters))
    emitters.push_back(std::make_unique<ToldWrapper>(std::move(e), alone));
  auto& second = static_cast<ToldWrapper&>(*emitters[2]);
  second.error = "emitter 2 failed";
  second.delay = std::chrono::milliseconds(30);
  static_cast<ToldWrapper&>(*emitters[5]).error = "emitter 5 failed";
  Scheduler scheduler(archive, ThresholdParams{0.01, 0.0}, std::move(emitters));
  Rng rng(3);
  tbb::task_arena arena(2);
  std::string message;
  arena.execute([&] {
    try {
      sphere_step(scheduler, rng);
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
  });
  return message;
}

TEST(SchedulerThreads, TheLowestEmitterErrorIsThrownAsInOrder) {
  EXPECT_EQ(error_of_a_round(false), "emitter 2 failed");
  EXPECT_EQ(error_of_a_round(true), "emitter 2 failed");
}

TEST(SchedulerThreads, AnEmitterThatDoesNotTellAloneIsToldInOrderOnTheCallingThread) {
  GridArchive archive(sphere_grid());
  std::vector<std::thread::id> threads;
  std::vector<int> order;
  std::vector<std::unique_ptr<Emitter>> emitters;
  int index = 0;
  for (auto& e : make_evolution_strategy_emitters(archive, told_emitter_params(), kToldEmitters)) {
    // One emitter that does not tell alone keeps the whole tell in order.
    const bool alone = index != 3;
    emitters.push_back(std::make_unique<ToldWrapper>(std::move(e), alone, &threads, &order, index));
    ++index;
  }
  Scheduler scheduler(archive, ThresholdParams{0.01, 0.0}, std::move(emitters));
  Rng rng(5);
  tbb::task_arena arena(2);
  arena.execute([&] {
    for (int i = 0; i < 5; ++i) sphere_step(scheduler, rng);
  });
  std::vector<int> expected;
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < kToldEmitters; ++k) expected.push_back(k);
  EXPECT_EQ(order, expected);
  const std::thread::id caller = std::this_thread::get_id();
  for (const std::thread::id& id : threads) EXPECT_EQ(id, caller);
}

}  // namespace
}  // namespace qdmeta
