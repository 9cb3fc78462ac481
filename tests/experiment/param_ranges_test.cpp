// The parameters declared once (IntParam / RealParam, core/params.hpp): the config reader reads
// each with its descriptor's range and meaning (the key log), and its component's validate()
// accepts both ends of that range and refuses what lies just outside them. A range written out a
// second time on either side, and differing, fails here (aurora.learning_rate was read as > 0
// while the autoencoder refused anything above 1000).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "expect_input_error.hpp"
#include "experiment/config_kinds.hpp"
#include "qdmeta/algorithms/aurora.hpp"
#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/control/controller.hpp"
#include "qdmeta/control/sarsa_control.hpp"
#include "qdmeta/control/state_tree.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/emitters/cell_thresholds.hpp"
#include "qdmeta/emitters/evolution_strategy_emitter.hpp"
#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "qdmeta/emitters/iso_line_emitter.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"
#ifdef QDMETA_TEST_RHEX
#include "qdmeta/tasks/rhex/rhex_meta_fitness.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#endif

namespace qdmeta {
namespace {

using Param = std::variant<IntParam, RealParam>;

// One parameter and a check that sets it to a value in its params struct and validates.
struct Probe {
  Param param;
  std::function<void(double)> validate_with;
};

template <class Params>
Probe probe(Param param, std::type_identity_t<void (*)(Params&, double)> set) {
  return {param, [set](double v) {
            Params p;
            set(p, v);
            p.validate();
          }};
}

std::string name_of(const Param& param) {
  return std::visit([](const auto& p) { return fmt::format("{}.{}", p.table, p.key); }, param);
}

std::vector<Probe> every_declared_parameter() {
  using AP = AuroraParams;
  using AE = AutoencoderParams;
  using UA = UnstructuredArchiveParams;
  using ST = StateTreeParams;
  using SP = SarsaParams;
  using ESE = EvolutionStrategyEmitterParams;
  std::vector<Probe> probes = {
      probe<MapElitesParams>(MapElitesParams::kBatchSize, [](auto& p, double v) { p.batch_size = static_cast<Index>(v); }),
      probe<MapElitesParams>(MapElitesParams::kInitialPopulation,
                             [](auto& p, double v) { p.initial_population = static_cast<Index>(v); }),
      probe<QdMetaParams>(QdMetaParams::kMetaPopulation, [](auto& p, double v) { p.meta_population = static_cast<Index>(v); }),
      probe<QdMetaParams>(QdMetaParams::kBatchSize, [](auto& p, double v) { p.batch_size = static_cast<Index>(v); }),
      probe<QdMetaParams>(QdMetaParams::kInitialPopulation,
                          [](auto& p, double v) { p.initial_population = static_cast<Index>(v); }),
      probe<QdMetaParams>(QdMetaParams::kDatabaseCapacity,
                          [](auto& p, double v) { p.database_capacity = static_cast<Index>(v); }),
      probe<QdMetaParams>(QdMetaParams::kHidden, [](auto& p, double v) { p.hidden = static_cast<Index>(v); }),
      probe<QdMetaParams>(QdMetaParams::kSigmoidScale, [](auto& p, double v) { p.sigmoid_scale = v; }),
      probe<QdMetaParams>(QdMetaParams::kCmaSigma, [](auto& p, double v) { p.cma_sigma = v; }),
      // AURORA's struct checks every key of [aurora]; the autoencoder and the archive check theirs again.
      probe<AP>(AP::kBatchSize, [](auto& p, double v) { p.batch_size = static_cast<Index>(v); }),
      probe<AP>(AP::kInitialPopulation, [](auto& p, double v) { p.initial_population = static_cast<Index>(v); }),
      probe<AP>(AE::kLatentSize, [](auto& p, double v) { p.latent_size = static_cast<Index>(v); }),
      probe<AP>(AE::kLearningRate, [](auto& p, double v) { p.learning_rate = v; }),
      probe<AP>(AE::kMaxEpochs, [](auto& p, double v) { p.max_epochs = static_cast<int>(v); }),
      probe<AP>(AE::kMaxTrainingRows, [](auto& p, double v) { p.max_training_rows = static_cast<Index>(v); }),
      probe<AP>(UA::kTargetSize, [](auto& p, double v) { p.target_size = static_cast<Index>(v); }),
      probe<AP>(UA::kEps, [](auto& p, double v) { p.eps = v; }),
      probe<AP>(UA::kNoveltyNeighbours, [](auto& p, double v) { p.novelty_neighbours = static_cast<int>(v); }),
      probe<AP>(AP::kSizeControlGain, [](auto& p, double v) { p.size_control_gain = v; }),
      probe<AP>(AP::kThresholdFactor, [](auto& p, double v) { p.threshold_factor = v; }),
      probe<AP>(AP::kRebuildEvery, [](auto& p, double v) { p.rebuild_every = static_cast<int>(v); }),
      probe<AP>(AP::kRetrainPeriodStep, [](auto& p, double v) { p.retrain_period_step = static_cast<int>(v); }),
      probe<AP>(AP::kRetrainPeriodMax, [](auto& p, double v) { p.retrain_period_max = static_cast<int>(v); }),
      probe<AE>(AE::kLatentSize, [](auto& p, double v) { p.latent_size = static_cast<Index>(v); }),
      probe<AE>(AE::kLearningRate, [](auto& p, double v) { p.learning_rate = v; }),
      probe<AE>(AE::kMaxEpochs, [](auto& p, double v) { p.max_epochs = static_cast<int>(v); }),
      probe<AE>(AE::kMaxTrainingRows, [](auto& p, double v) { p.max_training_rows = static_cast<Index>(v); }),
      // The archive's measure size is AURORA's latent size (its own range, checked against the one here).
      probe<UA>(AE::kLatentSize, [](auto& p, double v) { p.solution_size = 1, p.measure_size = static_cast<Index>(v); }),
      probe<UA>(UA::kTargetSize, [](auto& p, double v) { p.solution_size = 1, p.target_size = static_cast<Index>(v); }),
      probe<UA>(UA::kEps, [](auto& p, double v) { p.solution_size = 1, p.eps = v; }),
      probe<UA>(UA::kNoveltyNeighbours,
                [](auto& p, double v) { p.solution_size = 1, p.novelty_neighbours = static_cast<int>(v); }),
      // samples and init_samples are at least `centroids` besides: 1 here.
      probe<KMeansParams>(KMeansParams::kCentroids, [](auto& p, double v) { p.centroids = static_cast<Index>(v); }),
      probe<KMeansParams>(KMeansParams::kSamples,
                          [](auto& p, double v) { p.centroids = 1, p.samples = static_cast<Index>(v); }),
      probe<KMeansParams>(KMeansParams::kInitSamples,
                          [](auto& p, double v) { p.centroids = 1, p.init_samples = static_cast<Index>(v); }),
      probe<KMeansParams>(KMeansParams::kIterations, [](auto& p, double v) { p.iterations = static_cast<int>(v); }),
      probe<KMeansParams>(KMeansParams::kBatchSize, [](auto& p, double v) { p.batch_size = static_cast<Index>(v); }),
      probe<CvtMapElitesParams>(CvtMapElitesParams::kLookupChunk,
                                [](auto& p, double v) { p.lookup_chunk = static_cast<Index>(v); }),
      probe<CvtMapElitesParams>(CvtMapElitesParams::kNeighbours,
                                [](auto& p, double v) { p.neighbours = static_cast<Index>(v); }),
      probe<ST>(ST::kActions, [](auto& p, double v) { p.actions = static_cast<int>(v); }),
      probe<ST>(ST::kSplitMinTransitions, [](auto& p, double v) { p.split_min_transitions = static_cast<std::size_t>(v); }),
      probe<ST>(ST::kSplitProbability, [](auto& p, double v) { p.split_probability = v; }),
      probe<ST>(ST::kSplitMinFraction, [](auto& p, double v) { p.split_min_fraction = v; }),
      probe<ST>(ST::kMaxCandidates, [](auto& p, double v) { p.max_candidates = static_cast<std::size_t>(v); }),
      probe<ST>(ST::kMinValueGap, [](auto& p, double v) { p.min_value_gap = v; }),
      probe<ST>(ST::kKsAlpha, [](auto& p, double v) { p.ks_alpha = v; }),
      probe<SP>(ST::kActions, [](auto& p, double v) { p.actions = static_cast<int>(v); }),
      probe<SP>(SP::kMinGenerations, [](auto& p, double v) { p.min_generations = static_cast<int>(v); }),
      // max_generations is at least min_generations besides: 1 here.
      probe<SP>(SP::kMaxGenerations, [](auto& p, double v) { p.min_generations = 1, p.max_generations = static_cast<int>(v); }),
      probe<SP>(SP::kEpsilon, [](auto& p, double v) { p.epsilon = v; }),
      probe<SP>(SP::kGamma, [](auto& p, double v) { p.gamma = v; }),
      probe<SP>(SP::kAlpha, [](auto& p, double v) { p.alpha = v; }),
      probe<SP>(SP::kAlphaZeroReward, [](auto& p, double v) { p.alpha_zero_reward = v; }),
      probe<SP>(SP::kTraceDecay, [](auto& p, double v) { p.trace_decay = v; }),
      probe<SP>(SP::kTraceMin, [](auto& p, double v) { p.trace_min = v; }),
      probe<SP>(SP::kRewardScale, [](auto& p, double v) { p.reward_scale = v; }),
      probe<SP>(SP::kRewardMax, [](auto& p, double v) { p.reward_max = v; }),
      {StaticControl::kGenerations, [](double v) { StaticControl control(static_cast<int>(v)); }},
      // Each mutation key is checked for the kinds that read it.
      probe<MutationParams>(MutationParams::kRate, [](auto& p, double v) { p.rate = v; }),
      probe<MutationParams>(MutationParams::kSigma, [](auto& p, double v) { p.sigma = v; }),
      probe<MutationParams>(MutationParams::kStep, [](auto& p, double v) { p.kind = MutationKind::kDiscreteStep, p.step = v; }),
      probe<MutationParams>(MutationParams::kIsoSigma, [](auto& p, double v) { p.kind = MutationKind::kIsoLine, p.iso_sigma = v; }),
      probe<MutationParams>(MutationParams::kLineSigma, [](auto& p, double v) { p.kind = MutationKind::kIsoLine, p.line_sigma = v; }),
      probe<CmaMaeParams>(CmaMaeParams::kCount, [](auto& p, double v) { p.emitters = static_cast<int>(v); }),
      // [emitters]: CmaMaeParams checks x0 and each kind's keys through its emitter's struct, which
      // the Python emitters validate with too. A valid x0 of one gene besides the key probed.
      probe<CmaMaeParams>(CmaMaeParams::kX0, [](auto& p, double v) { p.emitter.x0 = {v}; }),
      probe<CmaMaeParams>(kEmitterBatchSize, [](auto& p, double v) { p.emitter.x0 = {0.5}, p.emitter.batch_size = static_cast<int>(v); }),
      probe<CmaMaeParams>(ESE::kSigma0, [](auto& p, double v) { p.emitter.x0 = {0.5}, p.emitter.sigma0 = v; }),
      probe<CmaMaeParams>(ESE::kRestartEvery, [](auto& p, double v) {
        p.emitter.x0 = {0.5}, p.emitter.restart = EmitterRestart::kEveryN, p.emitter.restart_every = static_cast<int>(v);
      }),
      probe<CmaMaeParams>(GaussianEmitterParams::kSigma, [](auto& p, double v) {
        p.emitter.x0 = {0.5}, p.kind = EmitterKind::kGaussian, p.sigma = v;
      }),
      probe<CmaMaeParams>(IsoLineEmitterParams::kIsoSigma, [](auto& p, double v) {
        p.emitter.x0 = {0.5}, p.kind = EmitterKind::kIsoLine, p.iso_sigma = v;
      }),
      probe<CmaMaeParams>(IsoLineEmitterParams::kLineSigma, [](auto& p, double v) {
        p.emitter.x0 = {0.5}, p.kind = EmitterKind::kIsoLine, p.line_sigma = v;
      }),
      probe<ThresholdParams>(ThresholdParams::kLearningRate, [](auto& p, double v) { p.alpha = v, p.threshold_min = 0.0; }),
      // -inf is CMA-ME's floor, at learning rate 1 only: here the rate is CMA-MAE's.
      probe<ThresholdParams>(ThresholdParams::kThresholdMin, [](auto& p, double v) { p.alpha = 0.5, p.threshold_min = v; }),
      probe<RastriginMetaParams>(RastriginMetaParams::kSampleFraction, [](auto& p, double v) { p.sample_fraction = v; }),
      probe<RastriginMetaParams>(RastriginMetaParams::kTransformRepetitions,
                                 [](auto& p, double v) { p.transform_repetitions = static_cast<int>(v); }),
      // Its upper bound is the task's N besides (tests/assembly/build_test.cpp).
      probe<RastriginMetaParams>(RastriginMetaParams::kDimensionCount,
                                 [](auto& p, double v) { p.dimension_count = static_cast<int>(v); }),
      probe<RastriginParams>(RastriginParams::kDimensions, [](auto& p, double v) { p.dimensions = static_cast<int>(v); }),
      probe<RastriginParams>(RastriginParams::kScoreM, [](auto& p, double v) { p.score_m = v; }),
  };
#ifdef QDMETA_TEST_RHEX
  using ES = rhex::EpisodeSettings;
  probes.push_back(probe<RhexParams>(RhexParams::kGeneStep, [](auto& p, double v) { p.gene_step = v; }));
  probes.push_back(probe<RhexParams>(rhex::RhexEnvironment::kDamagedLeg, [](auto& p, double v) {
    p.environment.damage = rhex::DamageType::kLegRemoval, p.environment.leg = static_cast<int>(v);
  }));
  probes.push_back(
      probe<RhexMetaParams>(RhexMetaParams::kSampleFraction, [](auto& p, double v) { p.sample_fraction = v; }));
  probes.push_back(probe<RhexParams>(ES::kTimeStep, [](auto& p, double v) { p.episode.time_step = v; }));
  probes.push_back(probe<RhexParams>(ES::kEpisodeSeconds, [](auto& p, double v) { p.episode.duration = v; }));
  probes.push_back(
      probe<RhexParams>(ES::kSettleSteps, [](auto& p, double v) { p.episode.settle_steps = static_cast<int>(v); }));
#endif
  return probes;
}

// The values at the ends of the range, and those just outside it (NaN and infinities for numbers).
struct Ends {
  std::vector<double> inside, outside;
};

Ends ends_of(const IntParam& p) {
  return {{static_cast<double>(p.lo), static_cast<double>(p.hi)},
          {static_cast<double>(p.lo - 1), static_cast<double>(p.hi + 1)}};
}

Ends ends_of(const RealParam& p) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const bool open_lo = p.open == Open::kLower || p.open == Open::kBoth;
  const bool open_hi = p.open == Open::kUpper || p.open == Open::kBoth;
  Ends e{{}, {std::numeric_limits<double>::quiet_NaN(), inf, -inf}};
  e.inside.push_back(open_lo ? std::nextafter(p.lo, inf) : p.lo);
  e.outside.push_back(open_lo ? p.lo : std::nextafter(p.lo, -inf));
  if (p.hi != kNoUpper) {
    e.inside.push_back(open_hi ? std::nextafter(p.hi, -inf) : p.hi);
    e.outside.push_back(open_hi ? p.hi : std::nextafter(p.hi, inf));
  } else {
    e.inside.push_back(kNoUpper);
  }
  return e;
}

// True when `message` refuses `name` for its range (another rule it breaks, e.g. a step that must
// divide 1, is no concern here).
bool out_of_range(const std::string& message, const std::string& name) {
  return message.starts_with(name + " = ") && message.find(" is out of range: must be ") != std::string::npos;
}

TEST(ParamRanges, ValidateAcceptsEachEndOfTheDeclaredRangeAndRefusesJustOutside) {
  for (const Probe& probe : every_declared_parameter()) {
    const std::string name = name_of(probe.param);
    const Ends ends = std::visit([](const auto& p) { return ends_of(p); }, probe.param);
    for (double v : ends.inside) {
      EXPECT_FALSE(out_of_range(input_error_message([&] { probe.validate_with(v); }), name))
          << name << " = " << v << " is inside the declared range but validate() refuses it";
    }
    for (double v : ends.outside) {
      const std::string message = input_error_message([&] { probe.validate_with(v); });
      EXPECT_TRUE(out_of_range(message, name)) << name << " = " << v << " lies outside the declared range: " << message;
      if (const auto* p = std::get_if<IntParam>(&probe.param)) {
        EXPECT_EQ(message, fmt::format("{} = {} is out of range: must be in [{}, {}]", name, v, p->lo, p->hi));
      }
    }
  }
}

TEST(ParamRanges, TheReaderReadsEachWithItsDescriptorsRangeAndMeaning) {
  const std::vector<ConfigKeyRecord> log = keys_the_code_reads();
  // A key may have one descriptor for each task that reads it (meta_fitness.sample_fraction:
  // Rastrigin's and RHex's, each with its own meaning): (range, meaning) of each, by key.
  std::map<std::string, std::set<std::pair<std::string, std::string>>> declared;
  for (const Probe& probe : every_declared_parameter()) {
    const std::string range = std::visit([](const auto& p) { return range_text(p); }, probe.param);
    const std::string_view doc = std::visit([](const auto& p) { return p.doc; }, probe.param);
    declared[name_of(probe.param)].insert({range, std::string(doc)});
  }
  for (const auto& [name, descriptors] : declared) {
    std::set<std::pair<std::string, std::string>> read;
    for (const ConfigKeyRecord& r : log) {
      if (r.key != name) continue;
      read.insert({r.range, r.doc});
      EXPECT_TRUE(descriptors.contains({r.range, r.doc}))
          << name << " is read with range " << r.range << " and meaning \"" << r.doc
          << "\": not through its descriptor";
    }
    for (const auto& [range, doc] : descriptors) {
      EXPECT_TRUE(read.contains({range, doc})) << name << " (" << range << ", " << doc << ") is read by no kind of config";
    }
  }
  // A descriptor the readers use but this test does not probe is a range nobody compares.
  for (const ConfigKeyRecord& r : log) {
    if (!r.doc.empty()) {
      EXPECT_TRUE(declared.contains(r.key)) << r.key << " is declared but not probed here";
    }
  }
}

// aurora.hidden, an array: two descriptors, each width's range and the number of layers. The
// reader reads with both and the autoencoder accepts the ends of both and refuses just outside.
TEST(ParamRanges, AuroraHiddenIsReadAndCheckedWithItsWidthAndLayerRanges) {
  using AE = AutoencoderParams;
  const IntParam width = AE::kHiddenWidth, layers = AE::kHiddenLayers;
  int read = 0;
  for (const ConfigKeyRecord& r : keys_the_code_reads()) {
    if (r.key != "aurora.hidden") continue;
    ++read;
    EXPECT_EQ(r.range, fmt::format("{} to {} entries, each {}", layers.lo, layers.hi, range_text(width)));
  }
  EXPECT_GT(read, 0) << "aurora.hidden is read by no kind of config";
  const auto check = [](std::vector<Index> hidden) {
    AE p;
    p.hidden = std::move(hidden);
    return input_error_message([&] { p.validate(); });
  };
  EXPECT_EQ(check({width.lo}), "(no InputError)");
  EXPECT_EQ(check({width.hi}), "(no InputError)");
  EXPECT_EQ(check({width.lo - 1}), fmt::format("aurora.hidden entry = {} is out of range: must be in [{}, {}]",
                                               width.lo - 1, width.lo, width.hi));
  EXPECT_EQ(check({width.hi + 1}), fmt::format("aurora.hidden entry = {} is out of range: must be in [{}, {}]",
                                               width.hi + 1, width.lo, width.hi));
  EXPECT_EQ(check(std::vector<Index>(static_cast<std::size_t>(layers.hi), 1)), "(no InputError)");
  EXPECT_EQ(check(std::vector<Index>(static_cast<std::size_t>(layers.hi + 1), 1)),
            fmt::format("aurora.hidden has {} entries: must have between {} and {}", layers.hi + 1, layers.lo, layers.hi));
  ASSERT_EQ(layers.lo, 1);  // fewer than one layer is the "empty" message
  EXPECT_EQ(check({}), "aurora.hidden is empty: give at least one hidden layer width");
}

}  // namespace
}  // namespace qdmeta
