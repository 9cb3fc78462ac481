// qdmeta-rhex-gait: replays one RHex controller and writes its gait as an animated HTML page or a
// CSV of poses. The controller comes from --genes or from a row of a run's archive.csv.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <array>
#include <fstream>
#include <sstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/tasks/rhex/gait_export.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace {

using namespace qdmeta;

std::array<Real, rhex::kGenes> parse_genes(const std::string& text) {
  std::array<Real, rhex::kGenes> g{};
  std::stringstream in(text);
  std::string item;
  int n = 0;
  while (std::getline(in, item, ',')) {
    if (n >= rhex::kGenes) throw InputError(fmt::format("--genes: more than {} values", rhex::kGenes));
    try {
      g[static_cast<std::size_t>(n++)] = std::stof(item);
    } catch (const std::exception&) {
      throw InputError(fmt::format("--genes: '{}' is not a number", item));
    }
  }
  if (n != rhex::kGenes) throw InputError(fmt::format("--genes: {} values given, {} needed", n, rhex::kGenes));
  return g;
}

std::array<Real, rhex::kGenes> archive_genes(const std::string& archive, Index row) {
  const EliteTable t = read_elites_csv(archive, EliteValues::kRunArchive);
  if (t.solutions.cols() != rhex::kGenes)
    throw InputError(fmt::format("--archive {}: solutions have {} genes, RHex needs {}", archive, t.solutions.cols(), rhex::kGenes));
  if (row < 0 || row >= t.size()) throw InputError(fmt::format("--row {} is out of range: the archive has {} rows", row, t.size()));
  std::array<Real, rhex::kGenes> g{};
  for (int j = 0; j < rhex::kGenes; ++j) g[static_cast<std::size_t>(j)] = t.solutions(row, j);
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"qdmeta-rhex-gait: replay an RHex controller and write its gait (HTML animation or CSV)"};
  std::string genes, archive, out, mjcf, course = "flat", damage = "none", legs = "rigid", engine = "dart";
  Index row = 0;
  int leg = 0;
  double seconds = 5.0;
  auto* g = app.add_option("--genes", genes, "24 comma-separated genes in [0, 1]");
  auto* a = app.add_option("--archive", archive, "archive.csv of a run (its solution_0..23 columns)");
  g->excludes(a);
  app.add_option("--row", row, "row of --archive (0 = first elite)");
  app.add_option("--course", course, "floor or obstacle course (docs/config.md, task.course)");
  app.add_option("--damage", damage, "damage (docs/config.md, task.damage)");
  app.add_option("--leg", leg, "damaged leg, 0..5");
  app.add_option("--legs", legs, "leg model: rigid or compliant");
  app.add_option("--engine", engine, "physics engine: dart or mujoco");
  app.add_option("--seconds", seconds, "episode length");
  app.add_option("--out", out, "output file: .html (animation) or .csv (poses)")->required();
  app.add_option("--mjcf", mjcf, "also write MuJoCo's model of the episode (MJCF) to this file");
  CLI11_PARSE(app, argc, argv);
  try {
    if (genes.empty() && archive.empty()) throw InputError("give --genes or --archive");
    const auto g24 = genes.empty() ? archive_genes(archive, row) : parse_genes(genes);
    RhexParams p;
    p.episode.duration = seconds;
    p.episode.record_poses = true;
    p.episode.legs = enum_from_string(rhex::kLegModelNames, "--legs", legs);
    p.episode.engine = enum_from_string(rhex::kEngineNames, "--engine", engine);
    rhex::RhexEnvironment env;
    env.course = enum_from_string(rhex::kObstacleCourseNames, "--course", course);
    env.damage = enum_from_string(rhex::kDamageTypeNames, "--damage", damage);
    env.leg = leg;
    env.validate();
    if (!mjcf.empty()) {
      std::ofstream file(mjcf);
      file << rhex::mujoco_model(p.episode, env);
      if (!file) throw InputError(fmt::format("--mjcf {}: cannot write", mjcf));
    }
    const RhexTask task(p);
    const rhex::EpisodeResult r = task.episode(g24.data(), env);
    if (out.ends_with(".csv")) rhex::write_gait_csv(r, out);
    else rhex::write_gait_html(r, out, fmt::format("RHex gait, {}: {:.2f} m{}", env.to_string(), r.fitness, r.dead ? " (dead)" : ""));
    fmt::print("{}: distance {:.9g} m{}, {} steps; wrote {}\n", env.to_string(), r.fitness, r.dead ? " (dead)" : "",
               r.walk_steps + r.settle_steps, out);
  } catch (const Error& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
  return 0;
}
