// MuJoCo's settings against the engine cross-check (docs/fidelity.md, "MuJoCo's settings against
// the cross-check"): the cross-check's random controllers (seed 3, the first `count` of its 200)
// on MuJoCo under each option variant (rhex_mujoco_variants.hpp), rigid and compliant legs, in a
// few environments, one episode at a time on this thread, each timed in this thread's CPU time
// (the machine's load counts less than in wall time). One CSV row per episode:
// variant,legs,environment,controller,distance,dead,cause,cpu_s (distance 0 when dead).
// tools/rhex_mujoco_settings_table.py compares each variant with the faithful one and with DART
// (the cross-check's committed episodes). Not a micro-benchmark: a plain program.
//   rhex_mujoco_settings [count=50] [legs=rigid,compliant] [envs=flat,many-pipes,slope]
//                        [variants=all] [header=1]
#include <fmt/format.h>

#include <ctime>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#include "tasks/key_value_args.hpp"
#include "tasks/rhex_mujoco_variants.hpp"

namespace {

using namespace qdmeta;

constexpr Index kCrosscheckControllers = 200;  // drawn in full, so that the first `count` are the cross-check's

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

rhex::RhexEnvironment environment(const std::string& name) {
  return rhex::RhexEnvironment::obstacle(enum_from_string(rhex::kObstacleCourseNames, "envs", name));
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{{"count", "50"},
                                          {"legs", "rigid,compliant"},
                                          {"envs", "flat,many-pipes,slope"},
                                          {"variants", "all"},
                                          {"header", "1"}};
  if (!bench::read_key_values(argc, argv, "rhex_mujoco_settings", args)) return 2;
  try {
    const Index count = std::stoll(args["count"]);
    if (count < 1 || count > kCrosscheckControllers)
      throw InputError(fmt::format("count = {}: must be in 1..{}", count, kCrosscheckControllers));
    Rng rng(3);  // the cross-check's seed
    RowMatrix g(kCrosscheckControllers, rhex::kGenes);
    for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
    std::vector<bench::MujocoVariant> variants;
    for (const auto& v : bench::rhex_mujoco_variants())
      if (args["variants"] == "all" || (',' + args["variants"] + ',').find(',' + v.name + ',') != std::string::npos)
        variants.push_back(v);
    if (variants.empty()) throw InputError(fmt::format("variants = {}: no such variant", args["variants"]));
    if (args["header"] == "1") fmt::print("variant,legs,environment,controller,distance,dead,cause,cpu_s\n");
    for (const std::string& legs_name : split(args["legs"])) {
      const auto legs = enum_from_string(rhex::kLegModelNames, "legs", legs_name);
      for (const std::string& env_name : split(args["envs"])) {
        const rhex::RhexEnvironment env = environment(env_name);
        for (const auto& v : variants) {
          RhexParams p;
          p.episode.legs = legs;
          bench::apply(v, p.episode);
          const RhexTask task(p);
          task.episode(g.row(0).data(), env);  // untimed: compiles the model and makes its mjData
          for (Index i = 0; i < count; ++i) {
            const double start = thread_seconds();
            const rhex::EpisodeResult r = task.episode(g.row(i).data(), env);
            const double cpu = thread_seconds() - start;
            const char* cause = !r.dead                                      ? ""
                                : r.turned_over                              ? "turned_over"
                                : r.settle_steps == p.episode.settle_steps ? "unsettled"
                                                                             : "diverged";
            fmt::print("{},{},{},{},{:.9g},{},{},{:.4g}\n", v.name, legs_name, env_name, i, r.dead ? 0.0 : r.fitness,
                       r.dead ? 1 : 0, cause, cpu);
          }
          std::fflush(stdout);
        }
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rhex_mujoco_settings: {}\n", e.what());
    return 2;
  }
  return 0;
}
