#include "random_search.hpp"

#include <qdmeta/assembly/build.hpp>
#include <qdmeta/assembly/standard_tables.hpp>
#include <qdmeta/core/error.hpp>
#include <qdmeta/core/rng.hpp>
#include <qdmeta/plugin/algorithm_registry.hpp>
#include <qdmeta/plugin/config.hpp>

#include <utility>

namespace arm {

RandomSearch::RandomSearch(qdmeta::MapElitesParams params, qdmeta::Task task,
                           std::unique_ptr<qdmeta::FeatureMap> feature_map, qdmeta::GridArchiveParams archive,
                           std::uint64_t seed)
    : params_(params), task_(std::move(task)), feature_map_(std::move(feature_map)), archive_(archive), seed_(seed) {
  params_.validate();
  qdmeta::check_map_elites_parts(task_, feature_map_.get(), archive_.solution_size(), archive_.dimensions());
}

void RandomSearch::next_request(std::vector<qdmeta::EvaluationJob>& jobs) {
  const qdmeta::Index n = task_.genotype_size();
  genotypes_.resize(generation_ == 0 ? params_.initial_population : params_.batch_size, n);
  // Generation g's own stream, whatever ran before: a resumed run draws what an uninterrupted
  // one does. (Generation 0 draws MAP-Elites's initial population.)
  qdmeta::Rng rng = qdmeta::Rng::stream(
      seed_, {qdmeta::key(qdmeta::StreamKey::kInitialPopulation), static_cast<std::uint64_t>(generation_)});
  qdmeta::random_genotypes(genotypes_, rng);
  evaluations_.resize(genotypes_.rows(), task_.base_feature_size());
  jobs.push_back({&task_, {genotypes_.data(), genotypes_.rows(), n}, evaluations_.view()});
}

bool RandomSearch::take_results() {
  qdmeta::insert_batch(archive_, *feature_map_, genotypes_, evaluations_, targets_);
  ++generation_;
  return true;
}

void RandomSearch::save(qdmeta::BinaryWriter& out) const {
  require_between_steps("save()");
  out.tag("random_search");
  out.value(generation_);
  qdmeta::save_counters(out, counters());
  archive_.save(out);
}

void RandomSearch::load(qdmeta::BinaryReader& in) {
  require_between_steps("load()");
  in.expect_tag("random_search");
  generation_ = in.value<std::int64_t>("generation");
  restore_counters(qdmeta::load_counters(in));
  archive_.load(in);
}

qdmeta::AlgorithmMaker build_random_search(qdmeta::AlgorithmBuild& build) {
  qdmeta::ConfigReader batches = build.root.table("map_elites");
  const qdmeta::MapElitesParams params = qdmeta::read_map_elites_table(batches);
  qdmeta::ConfigReader archive_table = build.root.table("archive");
  if (const std::string kind = qdmeta::read_archive_kind(archive_table); kind != "grid")
    throw qdmeta::InputError(archive_table.source() + ": archive.kind = \"" + kind +
                             "\": random-search's archive is a grid");
  qdmeta::GridArchiveParams grid = qdmeta::read_grid_table(archive_table);
  grid.solution_size = build.task.genotype_size();
  grid.qd_offset = build.task.qd_offset();
  qdmeta::ConfigReader feature_map_table = build.root.table("feature_map");
  auto feature_map = qdmeta::read_feature_map_table(feature_map_table, archive_table, build.task.base_feature_size(),
                                                    static_cast<qdmeta::Index>(grid.bins.size()));
  // What the run will allocate, checked against the machine before the maker is called.
  qdmeta::add_map_elites_memory(build.built.memory, params, build.task);
  build.built.memory.add("the archive", "archive.bins (cells) x genes", qdmeta::grid_archive_bytes(grid));
  return [params, task = std::move(build.task), feature_map = std::move(feature_map), grid,
          seed = build.settings.seed]() mutable -> std::unique_ptr<qdmeta::Algorithm> {
    return std::make_unique<RandomSearch>(params, std::move(task), std::move(feature_map), grid, seed);
  };
}

void register_random_search() { qdmeta::register_algorithm("random-search", build_random_search); }

}  // namespace arm
