// DART against MuJoCo (docs/fidelity.md, "MuJoCo"): the same random controllers, and the tripod
// gait, in every environment of the study (flat ground, the four damages on one leg, the nine
// courses) on DART with rigid legs (the reference), MuJoCo with rigid legs, and DART with
// compliant legs on the first `compliant` controllers (each ~1.5 s), and DART with rigid legs at a
// short step (`fine_dt`, the converged reference: docs/fidelity.md) on the first `fine`. Per environment and model:
// mean distance (dead = 0), deaths, the tripod's distance, and against DART-rigid over the same
// controllers Pearson's r and Spearman's rank correlation, and how many die on one engine only;
// deaths by cause: turned over (during the walk), never settled (after it), diverged (MuJoCo).
// MuJoCo's compliant legs: rhex_crosscheck (the committed cross-check). Not a micro-benchmark: a
// plain program.
//   rhex_engines [count=200] [seed=3] [threads=1] [leg=1] [compliant=0] [fine=0] [fine_dt=0.001] [seconds=5] [only=NAME]
// only: the environments whose name contains NAME.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#include "tasks/key_value_args.hpp"
#include "tasks/paired_stats.hpp"
#include "tasks/rhex_study_environments.hpp"
#include "tasks/rhex_time_step.hpp"

namespace {

using namespace qdmeta;

struct Model {
  std::string name;
  rhex::Engine engine;
  rhex::LegModel legs;
  bool subset;  // only the first `subset` controllers
  double time_step = 0.005;
  bool fine = false;  // DART at a short step: the converged reference (MuJoCo is compared with it too)
};

struct Outcome {
  std::vector<double> distance;  // 0 when dead
  std::vector<int> dead;
  int turned_over = 0, unsettled = 0, diverged = 0;  // the deaths by cause
  double drift = 0.0, turn = 0.0;  // mean |y| (m) and |yaw| (rad) at the end, dead or alive
  double tripod = 0.0;
  double seconds_per_episode = 0.0;
};

std::vector<double> head(const std::vector<double>& v, std::size_t n) { return {v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n)}; }

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{{"count", "200"}, {"seed", "3"},      {"threads", "1"},
                                          {"leg", "1"},     {"compliant", "0"}, {"seconds", "5"},
                                          {"only", ""},     {"fine", "0"},      {"fine_dt", "0.001"}};
  if (!bench::read_key_values(argc, argv, "rhex_engines", args)) return 2;
  try {
    const Index count = std::stoll(args["count"]);
    const auto subset = static_cast<std::size_t>(std::min<Index>(count, std::stoll(args["compliant"])));
    const auto fine = static_cast<std::size_t>(std::min<Index>(count, std::stoll(args["fine"])));
    const int leg = std::stoi(args["leg"]);
    const int threads = std::stoi(args["threads"]);
    Rng rng(std::stoull(args["seed"]));
    RowMatrix g(count, rhex::kGenes);
    for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
    std::vector<Model> models{{"DART rigid", rhex::Engine::kDart, rhex::LegModel::kRigid, false},
                              {"MuJoCo rigid", rhex::Engine::kMujoco, rhex::LegModel::kRigid, false}};
    if (subset > 0) models.push_back({"DART compliant", rhex::Engine::kDart, rhex::LegModel::kCompliant, true});
    if (fine > 0)
      models.push_back({fmt::format("DART {:g} ms", 1000 * std::stod(args["fine_dt"])), rhex::Engine::kDart,
                        rhex::LegModel::kRigid, true, std::stod(args["fine_dt"]), true});
    const auto envs = bench::rhex_study_environments(leg);
    auto evaluator = make_evaluator(threads);
    const auto tripod = rhex::tripod_genes();
    fmt::print("{} random controllers (seed {}), DART compliant on the first {}, DART at {} s on the first {}, {} threads; "
               "distance in m (dead = 0)\n",
               count, args["seed"], subset, args["fine_dt"], fine, threads);
    for (const auto& [env_name, env] : envs) {
      if (!args["only"].empty() && env_name.find(args["only"]) == std::string::npos) continue;
      std::vector<Outcome> outcomes;
      for (const auto& m : models) {
        RhexParams p;
        p.episode.engine = m.engine;
        p.episode.legs = m.legs;
        bench::set_time_step(p.episode, m.time_step);  // the same 5 s of settling at most, 0.15 s quiet
        p.episode.duration = std::stod(args["seconds"]);
        const RhexTask task(p);
        const Index n = m.fine ? static_cast<Index>(fine) : m.subset ? static_cast<Index>(subset) : count;
        Outcome o;
        o.distance.resize(static_cast<std::size_t>(n));
        o.dead.resize(static_cast<std::size_t>(n));
        const auto start = std::chrono::steady_clock::now();
        std::vector<int> cause(static_cast<std::size_t>(n));  // 1 turned over, 2 never settled, 3 diverged
        std::vector<double> drift(cause.size()), turn(cause.size());
        evaluator->parallel_for(n, [&](Index i) {
          const rhex::EpisodeResult r = task.episode(g.row(i).data(), env);
          const auto j = static_cast<std::size_t>(i);
          o.distance[j] = r.dead ? 0.0 : r.fitness;
          o.dead[j] = r.dead;
          if (r.dead) cause[j] = r.turned_over ? 1 : r.settle_steps == p.episode.settle_steps ? 2 : 3;
          drift[j] = std::abs(r.final_pose.y);
          turn[j] = std::abs(r.final_pose.yaw);
        });
        for (std::size_t j = 0; j < drift.size(); ++j) {
          o.drift += drift[j] / static_cast<double>(n);
          o.turn += turn[j] / static_cast<double>(n);
        }
        for (const int c : cause) {
          o.turned_over += c == 1;
          o.unsettled += c == 2;
          o.diverged += c == 3;
        }
        o.seconds_per_episode =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() * threads / static_cast<double>(n);
        const rhex::EpisodeResult t = task.episode(tripod.data(), env);
        o.tripod = t.dead ? 0.0 : t.fitness;
        outcomes.push_back(std::move(o));
      }
      fmt::print("{}:\n", env_name);
      for (std::size_t k = 0; k < models.size(); ++k) {
        const Outcome& o = outcomes[k];
        const std::size_t n = o.distance.size();
        double mean = 0;
        int dead = 0, dead_disagree = 0;
        for (std::size_t j = 0; j < n; ++j) {
          mean += o.distance[j] / static_cast<double>(n);
          dead += o.dead[j];
          dead_disagree += o.dead[j] != outcomes[0].dead[j];
        }
        fmt::print("  {:15s} n {:3d}, mean {:6.3f}, dead {:3d} (turned over {}, never settled {}, diverged {}), "
                   "|y| {:.2f}, |yaw| {:.2f}, tripod {:6.3f}, {:.3f} s/episode/core",
                   models[k].name, n, mean, dead, o.turned_over, o.unsettled, o.diverged, o.drift, o.turn, o.tripod,
                   o.seconds_per_episode);
        if (k > 0) {
          const auto ref = head(outcomes[0].distance, n);
          fmt::print("; vs DART rigid: r = {:.3f}, rank r = {:.3f}, dead on one only {}", bench::correlation(o.distance, ref),
                     bench::rank_correlation(o.distance, ref), dead_disagree);
        }
        if (k >= 2) {
          const auto mj = head(outcomes[1].distance, n);
          fmt::print("; MuJoCo rigid vs this: r = {:.3f}, rank r = {:.3f}", bench::correlation(mj, o.distance),
                     bench::rank_correlation(mj, o.distance));
          if (models[k].fine) {
            double mean_mj = 0;
            int dead_mj = 0;
            for (std::size_t j = 0; j < n; ++j) mean_mj += mj[j] / static_cast<double>(n), dead_mj += outcomes[1].dead[j];
            fmt::print(" (MuJoCo on these: mean {:.3f}, dead {})", mean_mj, dead_mj);
          }
        }
        fmt::print("\n");
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rhex_engines: {}\n", e.what());
    return 2;
  }
  return 0;
}
