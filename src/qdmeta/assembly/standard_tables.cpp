#include "qdmeta/assembly/standard_tables.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <limits>
#include <string>

#include "qdmeta/core/error.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/io/centroid_cache.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/part_registries.hpp"

namespace qdmeta {
namespace {

constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();

template <class E, std::size_t N>
std::vector<std::string> names_of(const EnumNames<E, N>& names) {
  std::vector<std::string> out;
  for (const auto& [e, name] : names) out.emplace_back(name);
  return out;
}

// Runs a part's reader, prefixing the InputError it may throw with the config file, as the
// reader's own messages are.
template <class F>
auto rethrow_with_source(const ConfigReader& table, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.starts_with(table.source())) throw;
    throw InputError(fmt::format("{}: {}", table.source(), what));
  }
}

const std::vector<std::string> kBuiltinArchives{"grid"};
const std::vector<std::string> kBuiltinFeatureMaps{"select"};

std::vector<std::string> joined(std::vector<std::string> builtin, const std::vector<std::string>& registered) {
  builtin.insert(builtin.end(), registered.begin(), registered.end());
  return builtin;
}

// A key the chosen kind does not read (iso-line's sigma) would be ignored silently: refused. A
// resolved config.toml records every key at its value in force, so one holding the default is
// let through (run directories written so far stay readable).
void refuse_unread_mutation_keys(const ConfigReader& m, const MutationParams& p) {
  const MutationParams defaults;
  const bool gaussian = p.kind == MutationKind::kGaussian, iso_line = p.kind == MutationKind::kIsoLine;
  const struct {
    const char* key;
    bool read;
    double value, fallback;
  } keys[] = {{"rate", !iso_line, p.rate, defaults.rate},
              {"sigma", gaussian, p.sigma, defaults.sigma},
              {"step", !gaussian && !iso_line, p.step, defaults.step},
              {"iso_sigma", iso_line, p.iso_sigma, defaults.iso_sigma},
              {"line_sigma", iso_line, p.line_sigma, defaults.line_sigma}};
  std::vector<std::string> read;
  for (const auto& k : keys)
    if (k.read) read.emplace_back(k.key);
  for (const auto& k : keys)
    if (!k.read && m.has(k.key) && k.value != k.fallback)
      throw InputError(fmt::format("{}: mutation.{} is not read by mutation kind \"{}\" (it reads {}): remove it",
                                   m.source(), k.key, enum_to_string(kMutationKindNames, p.kind),
                                   fmt::join(read, ", ")));
}

}  // namespace

std::vector<std::string> mutation_kinds() {
  return joined(names_of(kMutationKindNames), variation_registry().names());
}
std::vector<std::string> archive_kinds() { return joined(kBuiltinArchives, archive_registry().names()); }
std::vector<std::string> feature_map_kinds() { return joined(kBuiltinFeatureMaps, feature_map_registry().names()); }
std::vector<std::string> control_kinds() { return controller_registry().names(); }

MutationParams read_mutation_table(ConfigReader& m, const Task& task) {
  MutationParams p;
  const std::string kind = read_kind(m, names_of(kMutationKindNames), variation_registry().names(),
                                     enum_to_string(kMutationKindNames, p.kind));
  if (const auto reader = variation_registry().find(kind)) {
    p.variation = rethrow_with_source(m, [&] { return (*reader)(m, task); });
    if (!p.variation) throw InputError(fmt::format("{}: mutation kind \"{}\" made no operator", m.source(), kind));
    p.variation_name = kind;
    return p;
  }
  p.kind = enum_from_string(kMutationKindNames, "mutation.kind", kind);
  p.rate = m.number(MutationParams::kRate, p.rate);
  p.sigma = m.number(MutationParams::kSigma, p.sigma);
  p.step = m.number(MutationParams::kStep, p.step);
  p.iso_sigma = m.number(MutationParams::kIsoSigma, p.iso_sigma);
  p.line_sigma = m.number(MutationParams::kLineSigma, p.line_sigma);
  refuse_unread_mutation_keys(m, p);
  naming_source(m, [&] { p.validate(); });
  return p;
}

MapElitesParams read_map_elites_table(ConfigReader& me) {
  MapElitesParams p;
  p.batch_size = me.integer(MapElitesParams::kBatchSize, p.batch_size);
  p.initial_population = me.integer(MapElitesParams::kInitialPopulation, p.initial_population);
  return p;
}

GridArchiveParams read_grid_table(ConfigReader& a) {
  GridArchiveParams p;
  const auto bins = a.integers("bins", {100, 100}, 1, 100'000'000, 1, 16);
  p.bins.assign(bins.begin(), bins.end());
  p.lower = a.number("lower", p.lower, -kNoUpper, kNoUpper);
  p.upper = a.number("upper", p.upper, -kNoUpper, kNoUpper);
  p.solution_size = 1;  // completed by the algorithm from the task
  naming_source(a, [&] { p.validate(); });
  return p;
}

std::string read_archive_kind(ConfigReader& a) {
  return read_kind(a, kBuiltinArchives, archive_registry().names(), "grid");
}

AnyArchive read_registered_archive(ConfigReader& a, const std::string& kind, const Task& task, MemoryEstimate& memory) {
  const auto reader = archive_registry().find(kind);
  if (reader == nullptr) a.not_a_valid_choice("kind", kind, quoted_names(archive_registry().names()));
  return read_archive_with(a, kind, *reader, task, memory);
}

AnyArchive read_archive_with(ConfigReader& a, const std::string& kind, const ArchiveReader& reader, const Task& task,
                             MemoryEstimate& memory) {
  const ArchiveShape shape{task.genotype_size(), task.base_feature_size(), task.qd_offset()};
  AnyArchive archive = rethrow_with_source(a, [&] { return reader(a, shape, memory); });
  if (archive.solution_size() != shape.solution_size || archive.dimensions() < 1 ||
      (archive.base_feature_size() != 0 && archive.base_feature_size() != shape.base_feature_size) || !archive.empty())
    throw InputError(fmt::format("{}: archive kind \"{}\" made an archive of {} genes, {} dimensions and {} base "
                                 "features holding {} elites: it must be empty, hold {} genes, have a dimension and "
                                 "keep 0 or {} base features",
                                 a.source(), kind, archive.solution_size(), archive.dimensions(),
                                 archive.base_feature_size(), archive.size(), shape.solution_size,
                                 shape.base_feature_size));
  return archive;
}

std::unique_ptr<FeatureMap> read_feature_map_table(ConfigReader& f, ConfigReader& archive, Index base_features,
                                                   Index targets) {
  const std::string kind = read_kind(f, kBuiltinFeatureMaps, feature_map_registry().names(), "select");
  if (kind == "select") {
    // Without `measures`, target feature i is base feature i.
    // Name the key the user wrote: entry i of a grid's bins is base feature i.
    if (!archive.has("measures") && targets > base_features)
      throw InputError(fmt::format("{}: {} {} entries (one per target feature), but the task has {} base features: "
                                   "give at most {}, or archive.measures to pick a base feature for each",
                                   archive.source(), archive.has("kind") ? "the archive's dimensions have" : "archive.bins has",
                                   targets, base_features, base_features));
    std::vector<std::int64_t> fallback;
    for (Index i = 0; i < targets; ++i) fallback.push_back(i);
    const auto m = archive.integers("measures", fallback, 0, std::max<Index>(base_features - 1, 0),
                                    static_cast<std::size_t>(targets), static_cast<std::size_t>(targets),
                                    "one per entry of bins, each a base-feature index");
    return std::make_unique<SelectFeatureMap>(base_features, std::vector<int>(m.begin(), m.end()));
  }
  return read_feature_map_with(f, archive, kind, *feature_map_registry().find(kind), base_features, targets);
}

std::unique_ptr<FeatureMap> read_feature_map_with(ConfigReader& f, const ConfigReader& archive, const std::string& kind,
                                                  const FeatureMapReader& reader, Index base_features, Index targets) {
  if (archive.has("measures"))
    throw InputError(fmt::format("{}: archive.measures picks base features for feature_map.kind = \"select\"; "
                                 "feature-map \"{}\" makes the target features itself",
                                 archive.source(), kind));
  auto map = rethrow_with_source(f, [&] { return reader(f, base_features, targets); });
  if (!map || map->input_size() != base_features || map->output_size() != targets)
    throw InputError(fmt::format("{}: feature-map \"{}\" must map {} base features to {} target features", f.source(),
                                 kind, base_features, targets));
  return map;
}

SarsaParams read_sarsa_table(ConfigReader& c) {
  SarsaParams p;
  p.actions = static_cast<int>(c.integer(StateTreeParams::kActions, p.actions));
  p.min_generations = static_cast<int>(c.integer(SarsaParams::kMinGenerations, p.min_generations));
  p.max_generations = static_cast<int>(c.integer(SarsaParams::kMaxGenerations, p.max_generations));
  p.epsilon = c.number(SarsaParams::kEpsilon, p.epsilon);
  p.gamma = c.number(SarsaParams::kGamma, p.gamma);
  p.alpha = c.number(SarsaParams::kAlpha, p.alpha);
  p.alpha_zero_reward = c.number(SarsaParams::kAlphaZeroReward, p.alpha_zero_reward);
  p.trace_decay = c.number(SarsaParams::kTraceDecay, p.trace_decay);
  p.trace_min = c.number(SarsaParams::kTraceMin, p.trace_min);
  p.reward_scale = c.number(SarsaParams::kRewardScale, p.reward_scale);
  p.reward_max = c.number(SarsaParams::kRewardMax, p.reward_max);
  StateTreeParams& t = p.tree;
  t.split_min_transitions = static_cast<std::size_t>(
      c.integer(StateTreeParams::kSplitMinTransitions, static_cast<std::int64_t>(t.split_min_transitions)));
  t.split_probability = c.number(StateTreeParams::kSplitProbability, t.split_probability);
  t.split_min_fraction = c.number(StateTreeParams::kSplitMinFraction, t.split_min_fraction);
  t.max_candidates =
      static_cast<std::size_t>(c.integer(StateTreeParams::kMaxCandidates, static_cast<std::int64_t>(t.max_candidates)));
  t.min_value_gap = c.number(StateTreeParams::kMinValueGap, t.min_value_gap);
  t.ks_alpha = c.number(StateTreeParams::kKsAlpha, t.ks_alpha);
  return p;
}

std::unique_ptr<GenerationController> read_sarsa_control(ConfigReader& c) {
  const SarsaParams p = read_sarsa_table(c);
  return naming_source(c, [&] { return std::make_unique<SarsaControl>(p); });
}

std::unique_ptr<GenerationController> read_static_control(ConfigReader& c) {
  return std::make_unique<StaticControl>(static_cast<int>(c.integer(StaticControl::kGenerations, 5)));
}

std::unique_ptr<GenerationController> read_control_table(ConfigReader& c) {
  const std::string kind = read_kind(c, {}, controller_registry().names(), "sarsa");
  return read_control_with(c, kind, *controller_registry().find(kind));
}

std::unique_ptr<GenerationController> read_control_with(ConfigReader& c, const std::string& kind,
                                                        const ControllerReader& reader) {
  auto controller = rethrow_with_source(c, [&] { return reader(c); });
  if (!controller) throw InputError(fmt::format("{}: control kind \"{}\" made no controller", c.source(), kind));
  return controller;
}

// The [cvt] table's centroids: how they are made and cached.
CvtCentroidTable read_cvt_centroids(ConfigReader& c) {
  CvtCentroidTable table;
  CvtCentroidSettings& made = table.settings;
  KMeansParams& k = table.kmeans;
  k.centroids = c.integer(KMeansParams::kCentroids, k.centroids);
  k.samples = c.integer(KMeansParams::kSamples, k.samples);
  k.init = c.choice("init", k.init, kKMeansInitNames);
  k.init_samples = c.integer(KMeansParams::kInitSamples, k.init_samples);
  k.method = c.choice("method", k.method, kKMeansMethodNames);
  k.iterations = static_cast<int>(c.integer(KMeansParams::kIterations, k.iterations));
  k.batch_size = c.integer(KMeansParams::kBatchSize, k.batch_size);
  k.seed = static_cast<std::uint64_t>(c.integer("seed", static_cast<std::int64_t>(k.seed), 0, kMaxInt));
  const bool cache = c.boolean("cache", true);
  const std::string dir = c.string("cache_dir", "");
  if (cache) {
    made.cache_dir = dir.empty() ? default_centroid_cache_dir() : std::filesystem::path(dir);
    if (made.cache_dir.empty())
      throw InputError(fmt::format("{}: cvt.cache_dir is empty and neither XDG_CACHE_HOME nor HOME is set: "
                                   "give cvt.cache_dir or set cvt.cache = false", c.source()));
  }
  made.points = c.choice("points", made.points, kCvtPointsNames);
  if (made.points == CvtPoints::kRandomDescriptors)
    made.max_attempts = c.integer("max_attempts", made.max_attempts, 0, 1'000'000'000'000);
  try {
    k.validate();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", c.source(), e.what()));
  }
  return table;
}

// The [cvt] table: the centroids, and how offspring find their cells.
CvtTable read_cvt_table(ConfigReader& c) {
  CvtCentroidTable centroids = read_cvt_centroids(c);
  CvtTable table;
  CvtMapElitesParams& p = table.algorithm;
  p.kmeans = centroids.kmeans;
  table.centroids = std::move(centroids.settings);
  p.lookup_chunk = c.integer(CvtMapElitesParams::kLookupChunk, p.lookup_chunk);
  p.search = c.choice("search", p.search, kCvtSearchNames);
  p.neighbours = c.integer(CvtMapElitesParams::kNeighbours, p.neighbours);
  return table;
}

// The [aurora] table (docs/specification.md, AURORA).
AuroraParams read_aurora_table(ConfigReader& a) {
  AuroraParams p;
  p.batch_size = a.integer(AuroraParams::kBatchSize, p.batch_size);
  p.initial_population = a.integer(AuroraParams::kInitialPopulation, p.initial_population);
  p.latent_size = a.integer(AutoencoderParams::kLatentSize, p.latent_size);
  using AE = AutoencoderParams;
  const auto hidden = a.integers(AE::kHiddenWidth.key, std::vector<std::int64_t>(p.hidden.begin(), p.hidden.end()),
                                 AE::kHiddenWidth.lo, AE::kHiddenWidth.hi, AE::kHiddenLayers.lo, AE::kHiddenLayers.hi);
  p.hidden.assign(hidden.begin(), hidden.end());
  p.learning_rate = a.number(AutoencoderParams::kLearningRate, p.learning_rate);
  p.max_epochs = static_cast<int>(a.integer(AutoencoderParams::kMaxEpochs, p.max_epochs));
  p.max_training_rows = a.integer(AutoencoderParams::kMaxTrainingRows, p.max_training_rows);
  p.target_size = a.integer(UnstructuredArchiveParams::kTargetSize, p.target_size);
  p.eps = a.number(UnstructuredArchiveParams::kEps, p.eps);
  p.novelty_neighbours = static_cast<int>(a.integer(UnstructuredArchiveParams::kNoveltyNeighbours, p.novelty_neighbours));
  p.size_control_gain = a.number(AuroraParams::kSizeControlGain, p.size_control_gain);
  p.threshold_factor = a.number(AuroraParams::kThresholdFactor, p.threshold_factor);
  p.rebuild_every = static_cast<int>(a.integer(AuroraParams::kRebuildEvery, p.rebuild_every));
  p.retrain_period_step = static_cast<int>(a.integer(AuroraParams::kRetrainPeriodStep, p.retrain_period_step));
  p.retrain_period_max = static_cast<int>(a.integer(AuroraParams::kRetrainPeriodMax, p.retrain_period_max));
  return p;
}

void refuse_table(const ConfigReader& root, std::string_view name, std::string_view algorithm, std::string_view why) {
  if (root.has(name))
    throw InputError(fmt::format("{}: [{}] does not apply to algorithm \"{}\": {}", root.source(), name, algorithm, why));
}

}  // namespace qdmeta
