// The engine cross-check's episodes (docs/fidelity.md, "Cross-check, engine against engine"): the
// same random controllers (seed 3) and the tripod gait in every environment of the study, on the
// chosen engines and leg models at the authors' 5 ms step. One CSV row per episode
// (environment,model,controller,distance,dead,cause; controller: the random controller's index or
// "tripod"; distance 0 when dead; cause: turned_over, unsettled, diverged or empty), so that a
// long run can be cut into slices (from/to, only, models) whose rows are concatenated;
// tools/rhex_engines_table.py makes the table from them. Not a micro-benchmark: a plain program.
//   rhex_crosscheck [models=dart-rigid,mujoco-rigid] [count=200] [from=0] [to=count] [tripod=1]
//                   [seed=3] [leg=1] [threads=1] [env=K] [header=1]
// Models: dart-rigid, dart-compliant, mujoco-rigid, mujoco-compliant. env: only the K-th
// environment (0 flat, 1-4 the damages, 5-13 the courses). The seconds per episode per core go
// to stderr.
#include <fmt/format.h>

#include <chrono>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#include "tasks/key_value_args.hpp"
#include "tasks/rhex_study_environments.hpp"

namespace {

using namespace qdmeta;

struct Model {
  rhex::Engine engine;
  rhex::LegModel legs;
};

const std::map<std::string, Model> kModels{{"dart-rigid", {rhex::Engine::kDart, rhex::LegModel::kRigid}},
                                           {"dart-compliant", {rhex::Engine::kDart, rhex::LegModel::kCompliant}},
                                           {"mujoco-rigid", {rhex::Engine::kMujoco, rhex::LegModel::kRigid}},
                                           {"mujoco-compliant", {rhex::Engine::kMujoco, rhex::LegModel::kCompliant}}};

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');)
    if (!kModels.contains(item)) throw InputError(fmt::format("unknown model '{}'", item));
    else out.push_back(item);
  return out;
}

std::string row(const std::string& env, const std::string& model, const std::string& controller,
                const rhex::EpisodeResult& r, int settle_steps) {
  const char* cause = !r.dead ? "" : r.turned_over ? "turned_over" : r.settle_steps == settle_steps ? "unsettled" : "diverged";
  return fmt::format("{},{},{},{:.9g},{},{}\n", env, model, controller, r.dead ? 0.0 : r.fitness, r.dead ? 1 : 0, cause);
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{{"models", "dart-rigid,mujoco-rigid"},
                                          {"count", "200"}, {"from", "0"},   {"to", ""},      {"tripod", "1"},
                                          {"seed", "3"},    {"leg", "1"},    {"threads", "1"}, {"env", ""},
                                          {"header", "1"}};
  if (!bench::read_key_values(argc, argv, "rhex_crosscheck", args)) return 2;
  try {
    const Index count = std::stoll(args["count"]);
    const Index from = std::stoll(args["from"]);
    const Index to = args["to"].empty() ? count : std::min<Index>(count, std::stoll(args["to"]));
    const int threads = std::stoi(args["threads"]);
    Rng rng(std::stoull(args["seed"]));  // all `count` controllers, so that a slice has the same ones
    RowMatrix g(count, rhex::kGenes);
    for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
    const auto tripod = rhex::tripod_genes();
    auto evaluator = make_evaluator(threads);
    const std::vector<std::string> models = split(args["models"]);
    const auto envs = bench::rhex_study_environments(std::stoi(args["leg"]));
    if (args["header"] == "1") fmt::print("environment,model,controller,distance,dead,cause\n");
    for (std::size_t e = 0; e < envs.size(); ++e) {
      if (!args["env"].empty() && std::stoul(args["env"]) != e) continue;
      const auto& [env_name, env] = envs[e];
      for (const std::string& name : models) {
        RhexParams p;
        p.episode.engine = kModels.at(name).engine;
        p.episode.legs = kModels.at(name).legs;
        const RhexTask task(p);
        std::vector<std::string> rows(static_cast<std::size_t>(std::max<Index>(0, to - from)));
        const auto start = std::chrono::steady_clock::now();
        evaluator->parallel_for(static_cast<Index>(rows.size()), [&](Index k) {
          const Index i = from + k;
          rows[static_cast<std::size_t>(k)] =
              row(env_name, name, std::to_string(i), task.episode(g.row(i).data(), env), p.episode.settle_steps);
        });
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        for (const auto& r : rows) fmt::print("{}", r);
        if (args["tripod"] == "1")
          fmt::print("{}", row(env_name, name, "tripod", task.episode(tripod.data(), env), p.episode.settle_steps));
        std::fflush(stdout);
        if (!rows.empty())
          fmt::print(stderr, "{} {}: {:.3f} s/episode/core\n", env_name, name,
                     seconds * threads / static_cast<double>(rows.size()));
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rhex_crosscheck: {}\n", e.what());
    return 2;
  }
  return 0;
}
