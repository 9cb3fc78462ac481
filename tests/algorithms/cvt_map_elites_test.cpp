// CVT-MAP-Elites: same bits at any thread count, every elite in its nearest centroid's cell with
// its base features as descriptor, strictly-better replacement over a run, accounting.
#include "qdmeta/algorithms/cvt_map_elites.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "qdmeta/algorithms/descriptor_points.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

CvtMapElites cvt_on_rastrigin(std::uint64_t seed, CvtSearch search = CvtSearch::kParentBound, int dimensions = 20) {
  CvtMapElitesParams p;
  p.search = search;
  p.neighbours = 32;
  p.kmeans.centroids = 300;
  p.kmeans.samples = 6000;
  p.kmeans.init_samples = 3000;
  p.kmeans.iterations = 3;
  p.lookup_chunk = 30;
  RastriginParams task;
  task.dimensions = dimensions;
  return CvtMapElites(p, Task(RastriginTask(task)), {}, seed);
}

TEST(CvtMapElites, SameSeedSameBitsAtAnyThreadCount) {
  std::vector<EliteTable> results;
  for (int threads : {1, 2, 3}) {
    auto evaluator = make_evaluator(threads);
    CvtMapElites cvt = cvt_on_rastrigin(7);
    for (int g = 0; g < 30; ++g) cvt.step(*evaluator);
    results.push_back(cvt.elites());
  }
  for (std::size_t i = 1; i < results.size(); ++i) {
    EXPECT_EQ(results[i].index, results[0].index);
    EXPECT_EQ(results[i].objective, results[0].objective);
    EXPECT_TRUE(results[i].solutions == results[0].solutions);
    EXPECT_TRUE(results[i].measures == results[0].measures);
  }
}

TEST(CvtMapElites, ParentBoundAndBruteForceGiveTheSameArchive) {
  SerialEvaluator evaluator;
  CvtMapElites a = cvt_on_rastrigin(9, CvtSearch::kParentBound), b = cvt_on_rastrigin(9, CvtSearch::kBruteForce);
  for (int g = 0; g < 40; ++g) {
    a.step(evaluator);
    b.step(evaluator);
  }
  const EliteTable ta = a.elites(), tb = b.elites();
  EXPECT_EQ(ta.index, tb.index);
  EXPECT_EQ(ta.objective, tb.objective);
  EXPECT_TRUE(ta.solutions == tb.solutions);
}

// auto: the parent bound above 3 base features, no neighbour lists (the bucket grid) at 3 or
// fewer; every choice gives the same archive, each elite in its nearest centroid's cell.
TEST(CvtMapElites, AutoSearchPicksByDimensionAndEverySearchGivesTheSameArchive) {
  EXPECT_EQ(resolve_cvt_search(CvtSearch::kAuto, 20), CvtSearch::kParentBound);
  EXPECT_EQ(resolve_cvt_search(CvtSearch::kAuto, 4), CvtSearch::kParentBound);
  EXPECT_EQ(resolve_cvt_search(CvtSearch::kAuto, 3), CvtSearch::kBruteForce);
  EXPECT_EQ(resolve_cvt_search(CvtSearch::kAuto, 2), CvtSearch::kBruteForce);
  EXPECT_EQ(resolve_cvt_search(CvtSearch::kParentBound, 2), CvtSearch::kParentBound);
  EXPECT_EQ(resolve_cvt_search(CvtSearch::kBruteForce, 20), CvtSearch::kBruteForce);
  SerialEvaluator evaluator;
  for (int dimensions : {2, 3, 20}) {
    SCOPED_TRACE(::testing::Message() << dimensions << " base features");
    CvtMapElites automatic = cvt_on_rastrigin(11, CvtSearch::kAuto, dimensions);
    CvtMapElites parent = cvt_on_rastrigin(11, CvtSearch::kParentBound, dimensions);
    CvtMapElites brute = cvt_on_rastrigin(11, CvtSearch::kBruteForce, dimensions);
    for (int g = 0; g < 30; ++g) {
      automatic.step(evaluator);
      parent.step(evaluator);
      brute.step(evaluator);
    }
    EXPECT_EQ(automatic.archive().list_length(), dimensions > 3 ? 32 : 0);
    const EliteTable t = automatic.elites();
    ASSERT_GT(t.index.size(), 100u);
    for (const CvtMapElites* other : {&parent, &brute}) {
      const EliteTable o = other->elites();
      EXPECT_EQ(t.index, o.index);
      EXPECT_EQ(t.objective, o.objective);
      EXPECT_TRUE(t.solutions == o.solutions);
    }
    for (std::size_t i = 0; i < t.index.size(); ++i)
      ASSERT_EQ(t.index[i], nearest_centroid_naive(automatic.archive().centroids(), t.measures.row(static_cast<Index>(i)).data()));
  }
}

// The base features themselves as descriptors.
std::unique_ptr<FeatureMap> identity_map(Index features) {
  std::vector<int> all(static_cast<std::size_t>(features));
  for (int i = 0; i < static_cast<int>(features); ++i) all[static_cast<std::size_t>(i)] = i;
  return std::make_unique<SelectFeatureMap>(features, all);
}

// The generic MAP-Elites over a CVT archive (the base features as descriptors) is
// CVT-MAP-Elites: same parents, same cells, same elites, bit for bit.
TEST(CvtMapElites, GenericMapElitesOverACvtArchiveIsCvtMapElites) {
  SerialEvaluator evaluator;
  CvtMapElites cvt = cvt_on_rastrigin(5, CvtSearch::kBruteForce);
  cvt.prepare(evaluator);
  const Task task{RastriginTask()};
  CvtArchive archive(CvtArchiveParams{task.genotype_size(), task.qd_offset(), 0}, cvt.archive().centroids());
  BasicMapElites<CvtArchive> generic({}, task, identity_map(task.base_feature_size()), std::move(archive), {}, 5);
  for (int g = 0; g < 25; ++g) {
    cvt.step(evaluator);
    generic.step(evaluator);
  }
  const EliteTable a = cvt.elites(), b = generic.elites();
  ASSERT_GT(a.size(), 100);
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.objective, b.objective);
  EXPECT_TRUE(a.solutions == b.solutions);
  EXPECT_TRUE(a.measures == b.measures);
  EXPECT_EQ(cvt.counters(), generic.counters());
}

TEST(CvtMapElites, GenericMapElitesRefusesAnArchiveOfAnotherGenotypeSize) {
  const Task task{RastriginTask()};
  RowMatrix centroids = RowMatrix::Constant(10, task.base_feature_size(), 0.5f);
  try {
    CvtArchive wrong(CvtArchiveParams{task.genotype_size() + 1, 0.0, 0}, std::move(centroids));
    BasicMapElites<CvtArchive>({}, task, identity_map(task.base_feature_size()), std::move(wrong), {}, 5);
    FAIL() << "an archive of the wrong solution size was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solutions of 21 genes but task 'rastrigin' has 20"), std::string::npos)
        << e.what();
  }
}

TEST(CvtMapElites, ElitesSitInTheirNearestCentroidsCellWithTrueFitness) {
  SerialEvaluator evaluator;
  CvtMapElites cvt = cvt_on_rastrigin(3);
  EXPECT_EQ(cvt.elites().size(), 0);  // nothing before the first step
  EXPECT_EQ(cvt.stats(), ArchiveStats{});
  for (int g = 0; g < 20; ++g) cvt.step(evaluator);
  const EliteTable t = cvt.elites();
  ASSERT_GT(t.size(), 250);
  const RowMatrix& centroids = cvt.archive().centroids();
  for (Index i = 0; i < t.size(); ++i) {
    EXPECT_EQ(t.index[static_cast<std::size_t>(i)], nearest_centroid_naive(centroids, t.measures.row(i).data()));
    EXPECT_TRUE(t.measures.row(i) == t.solutions.row(i));  // Rastrigin's base features are the genes
    const double f = rastrigin::standard({t.solutions.row(i).data(), 20});
    EXPECT_NEAR(t.objective[static_cast<std::size_t>(i)], f, 1e-3 + 1e-5 * std::abs(f));
  }
  EXPECT_EQ(cvt.stats().num_elites, t.size());
  EXPECT_DOUBLE_EQ(cvt.stats().coverage, static_cast<double>(t.size()) / 300);
}

TEST(CvtMapElites, ArchiveNeverLosesAnEliteAndOnlyImproves) {
  SerialEvaluator evaluator;
  CvtMapElites cvt = cvt_on_rastrigin(11);
  cvt.step(evaluator);
  std::vector<Real> previous(300, -INFINITY);
  Index size = 0;
  double best = -INFINITY;
  int improved = 0;
  for (int g = 0; g < 60; ++g) {
    cvt.step(evaluator);
    const ArchiveStats s = cvt.stats();
    EXPECT_GE(s.num_elites, size);
    EXPECT_GE(s.obj_max, best);
    size = s.num_elites;
    best = s.obj_max;
    for (Index c = 0; c < 300; ++c) {
      if (!cvt.archive().occupied(c)) {
        EXPECT_EQ(previous[static_cast<std::size_t>(c)], -INFINITY);
        continue;
      }
      EXPECT_GE(cvt.archive().objective(c), previous[static_cast<std::size_t>(c)]);
      improved += cvt.archive().objective(c) > previous[static_cast<std::size_t>(c)];
      previous[static_cast<std::size_t>(c)] = cvt.archive().objective(c);
    }
  }
  EXPECT_GT(improved, 300);  // the run does improve its elites
}

// A task whose solutions with g0 < 0.3 are invalid ("dead") and leave NaN base features.
struct DeadWithNanFeaturesTask {
  Index genotype_size() const { return 3; }
  Index base_feature_size() const { return 3; }
  bool shareable() const { return true; }
  void evaluate(GenotypeView g, EvaluationView out) const {
    for (Index i = 0; i < g.count; ++i) {
      const bool alive = g.row(i)[0] >= 0.3f;
      out.valid[i] = alive;
      out.fitness[i] = g.row(i)[1];
      for (Index j = 0; j < 3; ++j) out.base_row(i)[j] = alive ? g.row(i)[j] : std::nanf("");
    }
  }
};

TEST(CvtMapElites, InvalidSolutionsNeverEnterAndTheirFeaturesAreIgnored) {
  CvtMapElitesParams p;
  p.kmeans.centroids = 50;
  p.kmeans.samples = 2000;
  p.kmeans.init_samples = 2000;
  p.kmeans.iterations = 2;
  p.neighbours = 8;
  CvtMapElites cvt(p, Task(DeadWithNanFeaturesTask{}), {}, 4);
  SerialEvaluator evaluator;
  for (int g = 0; g < 10; ++g) cvt.step(evaluator);
  const EliteTable t = cvt.elites();
  ASSERT_GT(t.size(), 20);
  for (Index i = 0; i < t.size(); ++i) EXPECT_GE(t.solutions(i, 0), 0.3f);
}

TEST(CvtMapElites, CountsInitialPopulationThenBatches) {
  SerialEvaluator evaluator;
  CvtMapElites cvt = cvt_on_rastrigin(5);
  cvt.step(evaluator);
  EXPECT_EQ(cvt.counters().bottom, 2000);
  cvt.step(evaluator);
  EXPECT_EQ(cvt.counters().bottom, 2400);
  EXPECT_EQ(cvt.counters().meta, 0);
  EXPECT_EQ(cvt.generation(), 2);
  EXPECT_EQ(cvt.name(), "cvt-map-elites");
}

TEST(CvtMapElites, ACheckpointedRunContinuesBitIdentically) {
  // The neighbour lists are made afresh on load; they only decide which centroids get the exact
  // check, so the archive continues exactly as if the run had never stopped.
  SerialEvaluator evaluator;
  CvtMapElites straight = cvt_on_rastrigin(12);
  for (int g = 0; g < 40; ++g) straight.step(evaluator);
  CvtMapElites first = cvt_on_rastrigin(12);
  for (int g = 0; g < 15; ++g) first.step(evaluator);
  BinaryWriter out;
  first.save(out);
  CvtMapElites second = cvt_on_rastrigin(12);
  BinaryReader in(out.bytes(), "memory");
  second.load(in);
  in.finish();
  EXPECT_EQ(second.archive().filled_cells(), first.archive().filled_cells());
  for (int g = 15; g < 40; ++g) second.step(evaluator);
  EXPECT_EQ(second.counters(), straight.counters());
  EXPECT_EQ(second.generation(), straight.generation());
  const EliteTable a = second.elites(), b = straight.elites();
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.objective, b.objective);
  EXPECT_TRUE(a.solutions == b.solutions);
}

TEST(CvtMapElites, ACheckpointBeforeTheFirstStepLoads) {
  CvtMapElites fresh = cvt_on_rastrigin(3);
  BinaryWriter out;
  fresh.save(out);
  CvtMapElites other = cvt_on_rastrigin(3);
  BinaryReader in(out.bytes(), "memory");
  other.load(in);
  EXPECT_FALSE(other.prepared());
  EXPECT_EQ(other.generation(), 0);
}

}  // namespace
}  // namespace qdmeta

namespace qdmeta {
namespace {

// `points = "random-descriptors"`: k-means over the base features of valid random genotypes only.
TEST(CvtMapElites, RandomDescriptorPointsAreTheValidGenotypesFeatures) {
  const Task task(DeadWithNanFeaturesTask{});
  SerialEvaluator serial;
  const DescriptorPoints d = feasible_random_descriptors(task, 500, 3, serial, 100'000, 64);
  ASSERT_EQ(d.points.rows(), 500);
  ASSERT_EQ(d.points.cols(), 3);
  for (Index i = 0; i < d.points.rows(); ++i) EXPECT_GE(d.points(i, 0), 0.3f);  // only the valid
  EXPECT_GT(d.attempts, 600);  // 30% of uniform genotypes are invalid: ~714 attempts
  EXPECT_LT(d.attempts, 900);
  auto threads = make_evaluator(2);
  EXPECT_TRUE(feasible_random_descriptors(task, 500, 3, *threads, 100'000, 64).points == d.points);
  EXPECT_THROW(feasible_random_descriptors(task, 500, 3, serial, 300, 64), Error);  // too few valid

}

}  // namespace
}  // namespace qdmeta
