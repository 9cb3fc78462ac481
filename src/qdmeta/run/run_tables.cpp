#include "qdmeta/run/run_tables.hpp"

namespace qdmeta {

namespace {

Cell integer(std::int64_t value) { return value; }

}  // namespace

RunPoint run_point(const Algorithm& algorithm, std::int64_t evals) {
  return {evals, algorithm.counters(), algorithm.generation(), algorithm.stats()};
}

const Table<RunPoint>& metrics_table() {
  // summary.json has counted generations under "generations" since it was first written.
  static const Table<RunPoint> table = {
      {"evals", [](const RunPoint& p) { return integer(p.evals); }},
      {"evals_bottom", [](const RunPoint& p) { return integer(p.counters.bottom); }},
      {"evals_meta", [](const RunPoint& p) { return integer(p.counters.meta); }},
      {"generation", [](const RunPoint& p) { return integer(p.generation); }, "generations"},
      {"num_elites", [](const RunPoint& p) { return integer(p.stats.num_elites); }},
      {"coverage", [](const RunPoint& p) { return Cell(p.stats.coverage); }},
      {"qd_score", [](const RunPoint& p) { return Cell(p.stats.qd_score); }},
      {"norm_qd_score", [](const RunPoint& p) { return Cell(p.stats.norm_qd_score); }},
      {"obj_max", [](const RunPoint& p) { return Cell(p.stats.obj_max); }},
      {"obj_mean", [](const RunPoint& p) { return Cell(p.stats.obj_mean); }},
  };
  return table;
}

const Table<MetaPoint>& meta_table() {
  static const Table<MetaPoint> table = {
      {"meta_generation", [](const MetaPoint& p) { return integer(p.record.meta_generation); }},
      {"evals", [](const MetaPoint& p) { return integer(p.evals); }},
      {"evals_bottom", [](const MetaPoint& p) { return integer(p.counters.bottom); }},
      {"evals_meta", [](const MetaPoint& p) { return integer(p.counters.meta); }},
      {"meta_fitness_best", [](const MetaPoint& p) { return Cell(p.record.meta_fitness_best); }},
      {"meta_fitness_mean", [](const MetaPoint& p) { return Cell(p.record.meta_fitness_mean); }},
      {"meta_fitness_sd", [](const MetaPoint& p) { return Cell(p.record.meta_fitness_sd); }},
      {"generations", [](const MetaPoint& p) { return integer(p.record.generations); }},
      {"states", [](const MetaPoint& p) { return integer(p.record.states); }},
      // Every map of the meta-generation: mean and standard error over the maps.
      {"population_num_elites_mean", [](const MetaPoint& p) { return Cell(p.record.population.num_elites.mean); }},
      {"population_num_elites_se", [](const MetaPoint& p) { return Cell(p.record.population.num_elites.se); }},
      {"population_obj_mean_mean", [](const MetaPoint& p) { return Cell(p.record.population.obj_mean.mean); }},
      {"population_obj_mean_se", [](const MetaPoint& p) { return Cell(p.record.population.obj_mean.se); }},
      {"population_obj_max_mean", [](const MetaPoint& p) { return Cell(p.record.population.obj_max.mean); }},
      {"population_obj_max_se", [](const MetaPoint& p) { return Cell(p.record.population.obj_max.se); }},
      {"population_qd_score_mean", [](const MetaPoint& p) { return Cell(p.record.population.qd_score.mean); }},
      {"population_qd_score_se", [](const MetaPoint& p) { return Cell(p.record.population.qd_score.se); }},
  };
  return table;
}

}  // namespace qdmeta
