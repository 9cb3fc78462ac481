// The ask/tell protocol of every algorithm: driving a step by hand (evaluating the jobs with
// their tasks) gives the same bits as step() with a serial and a thread evaluator; QD-Meta's
// request sequence has the documented shape; out-of-order calls and mis-shaped results are
// refused with their documented messages; checkpoints round-trip between hand-driven steps; a
// step that throws midway is undone, so stepping on gives the bits of a run it never failed in.
#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "qdmeta/algorithms/aurora.hpp"
#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/control/controller.hpp"
#include "qdmeta/control/sarsa_control.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"
#include "small_cma_mae.hpp"

namespace qdmeta {
namespace {

Task rastrigin(int dimensions) {
  RastriginParams rp;
  rp.dimensions = dimensions;
  return Task(RastriginTask(rp));
}

// Rastrigin that may not be shared between threads: QD-Meta then scores its maps in turn.
struct PrivateRastrigin {
  RastriginTask inner;
  std::string name() const { return "private-rastrigin"; }
  Index genotype_size() const { return inner.genotype_size(); }
  Index base_feature_size() const { return inner.base_feature_size(); }
  bool shareable() const { return false; }
  void evaluate(GenotypeView g, EvaluationView out) const { inner.evaluate(g, out); }
};

// A meta-objective that simulates: the mean fitness of every elite under two tasks (the run's
// Rastrigin and a 1-shifted copy of its fitness), drawn in a random order to use the stream.
struct ShiftedRastrigin {
  RastriginTask inner;
  std::string name() const { return "shifted"; }
  Index genotype_size() const { return inner.genotype_size(); }
  Index base_feature_size() const { return inner.base_feature_size(); }
  bool shareable() const { return true; }
  void evaluate(GenotypeView g, EvaluationView out) const {
    inner.evaluate(g, out);
    for (Index i = 0; i < out.count; ++i) out.fitness[i] += 1;
  }
};

class SimulatingMeta final : public MetaObjective {
 public:
  explicit SimulatingMeta(int dimensions) {
    RastriginParams rp;
    rp.dimensions = dimensions;
    tasks_ = {Task(RastriginTask(rp)), Task(ShiftedRastrigin{RastriginTask(rp)})};
  }
  std::string name() const override { return "simulating"; }
  MetaPlan plan(const MetaArchive& archive, Rng& rng) const override {
    const RowMatrix& elites = archive.genotypes();
    const Index n = elites.rows();
    RowMatrix shuffled(n, elites.cols());
    const std::vector<Index> order = sample_elites(n, n, rng);
    for (Index r = 0; r < n; ++r) shuffled.row(r) = elites.row(order[static_cast<std::size_t>(r)]);
    MetaPlan p;
    p.batches.push_back({0, shuffled});
    p.batches.push_back({1, shuffled.topRows((n + 1) / 2)});
    return p;
  }
  MetaFitnessResult score(const MetaArchive&, const MetaPlan& p, std::span<const EvaluationBatch> results) const override {
    double sum = 0;
    std::int64_t count = 0;
    for (std::size_t k = 0; k < p.batches.size(); ++k)
      for (Index r = 0; r < results[k].size(); ++r, ++count) sum += results[k].fitness[r];
    return {sum / static_cast<double>(count), count};
  }
  std::vector<Task> tasks() const override { return tasks_; }

 private:
  std::vector<Task> tasks_;
};

constexpr int kDims = 6;

MapElites make_map_elites() {
  MapElitesParams p;
  p.batch_size = 64;
  p.initial_population = 300;
  return MapElites(p, rastrigin(kDims), std::make_unique<SelectFeatureMap>(kDims, std::vector<int>{0, 1}), {}, {}, 4);
}

CvtMapElites make_cvt() {
  CvtMapElitesParams p;
  p.map_elites.batch_size = 64;
  p.map_elites.initial_population = 300;
  p.neighbours = 16;
  p.kmeans.centroids = 100;
  p.kmeans.samples = 2000;
  p.kmeans.init_samples = 1000;
  p.kmeans.iterations = 2;
  p.lookup_chunk = 20;
  return CvtMapElites(p, rastrigin(kDims), {}, 5);
}

Aurora make_aurora() {
  AuroraParams p;
  p.batch_size = 64;
  p.initial_population = 300;
  p.max_epochs = 5;
  p.target_size = 200;
  p.rebuild_every = 3;
  p.retrain_period_step = 2;
  return Aurora(p, rastrigin(kDims), {}, 6);
}

// CMA-MAE on a 10 x 10 grid of genes 0 and 1 (random-direction ranker, every-n restarts: the
// emitters' every stream is used), or on 60 CVT cells of the base features.
CmaMaeParams cma_mae_params() {
  CmaMaeParams p = test::small_cma_mae(kDims, 0.5, 3, 10, CmaBoundsHandling::kResample, {0.1, -100.0});
  p.emitter.ranker = EmitterRanker::kTwoStageRandomDirection;
  p.emitter.restart = EmitterRestart::kEveryN;
  p.emitter.restart_every = 3;
  return p;
}
std::unique_ptr<Algorithm> make_cma_mae() {
  CmaMaeParams p = cma_mae_params();
  p.emitter.measure_ranges = {1.0, 1.0};
  GridArchiveParams grid;
  grid.bins = {10, 10};
  grid.solution_size = kDims;
  return std::make_unique<CmaMae<GridArchive>>(p, rastrigin(kDims),
                                               std::make_unique<SelectFeatureMap>(kDims, std::vector<int>{0, 1}),
                                               [grid](Evaluator*) { return GridArchive(grid); }, 9);
}
std::unique_ptr<Algorithm> make_cma_mae_cvt() {
  CmaMaeParams p = cma_mae_params();
  p.emitter.measure_ranges.assign(kDims, 1.0);
  KMeansParams k;
  k.centroids = 60;
  k.samples = 1000;
  k.init_samples = 500;
  k.iterations = 2;
  return std::make_unique<CmaMae<CvtArchive>>(
      p, rastrigin(kDims), std::make_unique<SelectFeatureMap>(kDims, std::vector<int>{0, 1, 2, 3, 4, 5}),
      [k](Evaluator*) { return CvtArchive(CvtArchiveParams{kDims, 0.0, 0}, cvt_centroids(kDims, k).centroids); }, 10);
}

QdMeta make_qd_meta(std::unique_ptr<MetaObjective> objective, Task task = rastrigin(kDims), int generations = 2,
                    std::unique_ptr<GenerationController> controller = nullptr) {
  QdMetaParams p;
  p.meta_population = 3;
  p.batch_size = 40;
  p.initial_population = 150;
  p.database_capacity = 2000;
  GridArchiveParams grid;
  grid.bins = {10, 10};
  if (!controller) controller = std::make_unique<StaticControl>(generations);
  return QdMeta(p, std::move(task), std::move(objective), grid, {}, std::move(controller), 8);
}

std::unique_ptr<MetaObjective> translation() {
  RastriginMetaParams mp;
  mp.sample_fraction = 0.5;
  return std::make_unique<RastriginTranslationMeta>(mp);
}

// One step by hand: every job evaluated by its own task, in place. Returns the job count of
// each request.
std::vector<std::size_t> drive_step(Algorithm& a) {
  std::vector<std::size_t> requests;
  do {
    const std::span<const EvaluationJob> jobs = a.ask();
    requests.push_back(jobs.size());
    for (const EvaluationJob& j : jobs) j.task->evaluate(j.genotypes, j.out);
    a.tell();
  } while (a.step_in_progress());
  return requests;
}

void expect_same(const Algorithm& a, const Algorithm& b) {
  EXPECT_EQ(a.generation(), b.generation());
  EXPECT_EQ(a.counters(), b.counters());
  const ArchiveStats sa = a.stats(), sb = b.stats();
  EXPECT_EQ(sa.num_elites, sb.num_elites);
  EXPECT_EQ(sa.qd_score, sb.qd_score);
  EXPECT_EQ(sa.obj_max, sb.obj_max);
  const EliteTable ea = a.elites(), eb = b.elites();
  ASSERT_EQ(ea.size(), eb.size());
  EXPECT_GT(ea.size(), 0);
  EXPECT_EQ(ea.index, eb.index);
  EXPECT_EQ(ea.objective, eb.objective);
  EXPECT_TRUE(ea.solutions == eb.solutions);
  EXPECT_TRUE(ea.measures == eb.measures);
}

// Hand-driven steps against step() with a serial and a two-thread evaluator.
void expect_hand_equals_step(const std::function<std::unique_ptr<Algorithm>()>& make, int steps) {
  auto by_hand = make();
  for (int s = 0; s < steps; ++s) drive_step(*by_hand);
  SerialEvaluator serial;
  auto threads = make_thread_evaluator(2, 16);
  for (Evaluator* evaluator : {static_cast<Evaluator*>(&serial), threads.get()}) {
    auto stepped = make();
    for (int s = 0; s < steps; ++s) stepped->step(*evaluator);
    SCOPED_TRACE(evaluator->workers());
    expect_same(*by_hand, *stepped);
  }
}

TEST(AskTell, MapElitesByHandEqualsStep) {
  expect_hand_equals_step([] { return std::make_unique<MapElites>(make_map_elites()); }, 12);
}

TEST(AskTell, CvtMapElitesByHandEqualsStep) {
  expect_hand_equals_step([] { return std::make_unique<CvtMapElites>(make_cvt()); }, 12);
}

TEST(AskTell, AuroraByHandEqualsStep) {
  expect_hand_equals_step([] { return std::make_unique<Aurora>(make_aurora()); }, 12);
}

TEST(AskTell, CmaMaeByHandEqualsStep) {
  expect_hand_equals_step(make_cma_mae, 12);
  expect_hand_equals_step(make_cma_mae_cvt, 12);
}

TEST(AskTell, QdMetaByHandEqualsStep) {
  expect_hand_equals_step([] { return std::make_unique<QdMeta>(make_qd_meta(translation())); }, 5);
}

TEST(AskTell, QdMetaWithASimulatingObjectiveByHandEqualsStep) {
  expect_hand_equals_step([] { return std::make_unique<QdMeta>(make_qd_meta(std::make_unique<SimulatingMeta>(kDims))); }, 5);
  // An unshareable task: the maps are scored in turn, with the same bits.
  expect_hand_equals_step(
      [] {
        RastriginParams rp;
        rp.dimensions = kDims;
        return std::make_unique<QdMeta>(
            make_qd_meta(std::make_unique<SimulatingMeta>(kDims), Task(PrivateRastrigin{RastriginTask(rp)})));
      },
      4);
}

TEST(AskTell, ASingleJobPerStepForTheSingleArchiveAlgorithms) {
  MapElites me = make_map_elites();
  EXPECT_EQ(me.ask()[0].genotypes.count, 300);  // the initial population
  me.tell();
  const std::span<const EvaluationJob> jobs = me.ask();
  ASSERT_EQ(jobs.size(), 1U);
  EXPECT_EQ(jobs[0].genotypes.count, 64);
  EXPECT_EQ(jobs[0].out.count, 64);
  EXPECT_EQ(jobs[0].out.base_feature_size, kDims);
}

TEST(AskTell, QdMetaRequestsHaveTheDocumentedShape) {
  // No simulation in the meta-objective: G requests of lambda jobs per meta-generation, after
  // the initial population's one job in the first step.
  QdMeta q = make_qd_meta(translation(), rastrigin(kDims), 3);
  const std::span<const EvaluationJob> first = q.ask();
  ASSERT_EQ(first.size(), 1U);
  EXPECT_EQ(first[0].genotypes.count, 150);
  for (const EvaluationJob& j : first) j.task->evaluate(j.genotypes, j.out);
  q.tell();
  EXPECT_TRUE(q.step_in_progress());
  std::vector<std::size_t> rest;
  do {
    const std::span<const EvaluationJob> jobs = q.ask();
    rest.push_back(jobs.size());
    for (const EvaluationJob& j : jobs) {
      EXPECT_EQ(j.genotypes.count, 40);
      j.task->evaluate(j.genotypes, j.out);
    }
    q.tell();
  } while (q.step_in_progress());
  EXPECT_EQ(rest, (std::vector<std::size_t>{3, 3, 3}));
  EXPECT_EQ(drive_step(q), (std::vector<std::size_t>{3, 3, 3}));
  EXPECT_EQ(q.generation(), 2);

  // A simulating objective adds one request: its two batches per map, map-major.
  QdMeta s = make_qd_meta(std::make_unique<SimulatingMeta>(kDims), rastrigin(kDims), 2);
  EXPECT_EQ(drive_step(s), (std::vector<std::size_t>{1, 3, 3, 6}));
  std::vector<std::size_t> shape;
  do {
    const std::span<const EvaluationJob> jobs = s.ask();
    shape.push_back(jobs.size());
    if (jobs.size() == 6)
      for (std::size_t k = 0; k < 6; k += 2) {  // each map: all its elites, then half of them
        EXPECT_EQ(jobs[k + 1].genotypes.count, (jobs[k].genotypes.count + 1) / 2);
        EXPECT_EQ(jobs[k + 1].task->name(), "shifted");
      }
    for (const EvaluationJob& j : jobs) j.task->evaluate(j.genotypes, j.out);
    s.tell();
  } while (s.step_in_progress());
  EXPECT_EQ(shape, (std::vector<std::size_t>{3, 3, 6}));
  // Meta evaluations: every job of the last request, as the objective counted them.
  EXPECT_GT(s.counters().meta, 0);
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(AskTell, OutOfOrderCallsAreRefused) {
  MapElites me = make_map_elites();
  EXPECT_EQ(message_of([&] { me.tell(); }), "map-elites: tell() called with no pending ask()");
  me.ask();
  EXPECT_TRUE(me.request_pending());
  EXPECT_EQ(message_of([&] { me.ask(); }), "map-elites: ask() called again before tell() of the previous request");
  SerialEvaluator serial;
  EXPECT_THROW(me.step(serial), Error);
  BinaryWriter out;
  EXPECT_NE(message_of([&] { me.save(out); }).find("save() in the middle of a step"), std::string::npos);
  me.tell();  // outputs still zero: every row invalid, so nothing enters
  EXPECT_FALSE(me.request_pending());
  EXPECT_EQ(me.stats().num_elites, 0);
  EXPECT_EQ(message_of([&] { me.tell(); }), "map-elites: tell() called with no pending ask()");

  // QD-Meta between its requests: mid-step, so no checkpoint and no step().
  QdMeta q = make_qd_meta(translation());
  drive_step(q);
  const std::span<const EvaluationJob> jobs = q.ask();
  for (const EvaluationJob& j : jobs) j.task->evaluate(j.genotypes, j.out);
  q.tell();
  EXPECT_TRUE(q.step_in_progress());
  EXPECT_FALSE(q.request_pending());
  EXPECT_NE(message_of([&] { q.save(out); }).find("qd-meta: save() in the middle of a step"), std::string::npos);
  EXPECT_NE(message_of([&] { q.step(serial); }).find("step() in the middle of a step"), std::string::npos);
  BinaryReader empty(std::string_view{}, "memory");
  EXPECT_NE(message_of([&] { q.load(empty); }).find("load() in the middle of a step"), std::string::npos);
}

TEST(AskTell, CopyingTellChecksShapesAndEqualsInPlaceTell) {
  MapElites me = make_map_elites(), reference = make_map_elites();
  for (int step = 0; step < 4; ++step) {
    const std::span<const EvaluationJob> jobs = me.ask();
    std::vector<EvaluationBatch> mine(1);
    mine[0].resize(jobs[0].genotypes.count, kDims);
    jobs[0].task->evaluate(jobs[0].genotypes, mine[0].view());
    if (step == 1) {
      std::vector<EvaluationBatch> two(2, mine[0]);
      EXPECT_EQ(message_of([&] { me.tell(two); }), "map-elites: tell() got 2 result blocks for a request of 1 jobs");
      std::vector<EvaluationBatch> short_rows(1);
      short_rows[0].resize(jobs[0].genotypes.count - 1, kDims);
      EXPECT_THROW(me.tell(short_rows), InputError);
      EXPECT_NE(message_of([&] { me.tell(short_rows); }).find("job 0 (task 'rastrigin') has 64 rows"), std::string::npos);
      std::vector<EvaluationBatch> narrow(1);
      narrow[0].resize(jobs[0].genotypes.count, kDims - 1);
      EXPECT_NE(message_of([&] { me.tell(narrow); }).find("has 6 base features, but its result block has 5"),
                std::string::npos);
      std::vector<EvaluationBatch> bad = mine;
      bad[0].valid[3] = 1;
      bad[0].fitness[3] = std::numeric_limits<Real>::quiet_NaN();
      EXPECT_NE(message_of([&] { me.tell(bad); }).find("job 0 row 3: fitness nan is not finite"), std::string::npos);
      bad = mine;
      bad[0].valid[5] = 1;
      bad[0].base_features(5, 2) = 1.5F;
      EXPECT_NE(message_of([&] { me.tell(bad); }).find("job 0 row 5: base feature 2 is 1.5, outside [0, 1]"),
                std::string::npos);
      EXPECT_TRUE(me.request_pending());  // a refused tell() leaves the request pending
    }
    me.tell(mine);
    drive_step(reference);
  }
  expect_same(me, reference);
}

TEST(AskTell, CheckpointsRoundTripBetweenHandDrivenSteps) {
  QdMeta straight = make_qd_meta(std::make_unique<SimulatingMeta>(kDims));
  for (int t = 0; t < 6; ++t) drive_step(straight);
  QdMeta first = make_qd_meta(std::make_unique<SimulatingMeta>(kDims));
  for (int t = 0; t < 3; ++t) drive_step(first);
  BinaryWriter out;
  first.save(out);
  QdMeta second = make_qd_meta(std::make_unique<SimulatingMeta>(kDims));
  BinaryReader in(out.bytes(), "memory");
  second.load(in);
  in.finish();
  EXPECT_EQ(drive_step(second).size(), 3U);  // no initial population after a load
  for (int t = 0; t < 2; ++t) drive_step(second);
  expect_same(second, straight);
  EXPECT_EQ(second.meta_fitness(), straight.meta_fitness());
  EXPECT_TRUE(second.database() == straight.database());
}

TEST(AskTell, MetaObjectiveEvaluateIsPlanThenScore) {
  const SimulatingMeta meta(kDims);
  RowMatrix elites = RowMatrix::Random(20, kDims).cwiseAbs();
  Rng a(3), b(3);
  SerialEvaluator serial;
  const MetaFitnessResult whole = meta.evaluate(elites, a, serial);
  const MetaPlan plan = meta.plan(elites, b);
  ASSERT_EQ(plan.batches.size(), 2U);
  std::vector<EvaluationBatch> results(2);
  const std::vector<Task> tasks = meta.tasks();
  for (std::size_t k = 0; k < 2; ++k) {
    const RowMatrix& g = plan.batches[k].genotypes;
    results[k].resize(g.rows(), kDims);
    tasks[static_cast<std::size_t>(plan.batches[k].task)].evaluate({g.data(), g.rows(), g.cols()}, results[k].view());
  }
  const MetaFitnessResult parts = meta.score(elites, plan, results);
  EXPECT_EQ(whole.value, parts.value);
  EXPECT_EQ(whole.evaluations, 30);
  EXPECT_EQ(a.state(), b.state());

  MetaPlan wrong = plan;
  wrong.batches[1].task = 2;
  EXPECT_EQ(message_of([&] { check_meta_plan(meta, wrong, tasks); }),
            "meta-objective 'simulating': batch 1 names task 2, but tasks() lists 2");
}


// A task that crashes now and then: evaluate() throws on its chosen calls (counted from 1).
class FlakyEvaluator final : public Evaluator {
 public:
  explicit FlakyEvaluator(std::set<int> failing) : failing_(std::move(failing)) {}
  void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) override {
    if (failing_.contains(++calls_)) throw std::runtime_error("the simulator crashed");
    task.evaluate(genotypes, out);
  }
  int workers() const override { return 1; }

 private:
  std::set<int> failing_;
  int calls_ = 0;
};

// `steps` steps with a flaky evaluator, each failed step stepped again, against the same steps
// that never failed.
void expect_failed_steps_undone(const std::function<std::unique_ptr<Algorithm>()>& make, int steps,
                                std::set<int> failing) {
  auto straight = make();
  SerialEvaluator serial;
  for (int s = 0; s < steps; ++s) straight->step(serial);
  auto flaky = make();
  FlakyEvaluator evaluator(failing);
  std::size_t failures = 0;
  for (int s = 0; s < steps; ++s) {
    for (;;) {
      try {
        flaky->step(evaluator);
        break;
      } catch (const std::runtime_error& e) {
        ASSERT_STREQ(e.what(), "the simulator crashed");
        ASSERT_FALSE(flaky->step_in_progress());
        ASSERT_EQ(flaky->generation(), s);
        ++failures;
      }
    }
  }
  EXPECT_EQ(failures, failing.size());
  expect_same(*straight, *flaky);
}

TEST(StepUndo, AFailedMapElitesStepIsUndone) {
  // The initial population's call fails, then one call twice running.
  expect_failed_steps_undone([] { return std::make_unique<MapElites>(make_map_elites()); }, 8, {1, 4, 5});
}

TEST(StepUndo, AFailedCvtMapElitesStepIsUndone) {
  expect_failed_steps_undone([] { return std::make_unique<CvtMapElites>(make_cvt()); }, 8, {1, 4, 5});
}

TEST(StepUndo, AFailedCmaMaeStepIsUndone) {
  // The first step fails (its scheduler made, and asked, inside it), then one twice running.
  expect_failed_steps_undone(make_cma_mae, 12, {1, 4, 5});
  expect_failed_steps_undone(make_cma_mae_cvt, 12, {1, 7});
}

TEST(StepUndo, AFailedAuroraStepIsUndone) {
  expect_failed_steps_undone([] { return std::make_unique<Aurora>(make_aurora()); }, 8, {1, 4, 5});
}

TEST(StepUndo, AFailedQdMetaStepIsUndoneAtAnyRequest) {
  // A step: the seeds (first step only), 2 generations of 3 maps, then the meta-objective's
  // batches; calls 3 and 9 fail after the seeds went into the database, later ones in later
  // meta-generations, after CMA-ES's ask and the controller's choice.
  const std::set<int> failing = {2, 3, 9, 15, 16, 30};
  expect_failed_steps_undone([] { return std::make_unique<QdMeta>(make_qd_meta(std::make_unique<SimulatingMeta>(kDims))); },
                             5, failing);
  // SARSA learns inside its choice of G: that too is undone.
  expect_failed_steps_undone(
      [] {
        return std::make_unique<QdMeta>(make_qd_meta(std::make_unique<SimulatingMeta>(kDims), rastrigin(kDims), 2,
                                                     std::make_unique<SarsaControl>(SarsaParams{})));
      },
      5, failing);
}

// A meta-objective that fails once, in plan(): QD-Meta's step then throws from its last tell().
class FailingOnceMeta final : public MetaObjective {
 public:
  explicit FailingOnceMeta(int fail_at) : inner_(kDims), fail_at_(fail_at) {}
  std::string name() const override { return "failing-once"; }
  MetaPlan plan(const MetaArchive& archive, Rng& rng) const override {
    if (++(*calls_) == fail_at_) throw std::runtime_error("the simulator crashed");
    return inner_.plan(archive, rng);
  }
  MetaFitnessResult score(const MetaArchive& e, const MetaPlan& p, std::span<const EvaluationBatch> r) const override {
    return inner_.score(e, p, r);
  }
  std::vector<Task> tasks() const override { return inner_.tasks(); }

 private:
  SimulatingMeta inner_;
  int fail_at_;
  std::shared_ptr<std::atomic<int>> calls_ = std::make_shared<std::atomic<int>>(0);
};

TEST(StepUndo, AQdMetaStepWhoseMetaObjectiveFailsIsUndone) {
  QdMeta straight = make_qd_meta(std::make_unique<SimulatingMeta>(kDims));
  QdMeta failing = make_qd_meta(std::make_unique<FailingOnceMeta>(5));  // map 2 of meta-generation 2
  SerialEvaluator serial;
  for (int t = 0; t < 3; ++t) straight.step(serial);
  failing.step(serial);
  EXPECT_THROW(failing.step(serial), std::runtime_error);
  EXPECT_EQ(failing.generation(), 1);
  for (int t = 0; t < 2; ++t) failing.step(serial);
  expect_same(failing, straight);
  EXPECT_EQ(failing.meta_fitness(), straight.meta_fitness());
  EXPECT_TRUE(failing.database() == straight.database());
}

}  // namespace
}  // namespace qdmeta
