// Physics sanity of the RHex model (docs/fidelity.md, bench/README.md): how often random
// controllers die (turn over or never settle), how far they tilt, and how far they walk, under
// a chosen leg model, course and episode length. Not a micro-benchmark: a plain program.
//   rhex_sanity [count=200] [seed=2] [legs=rigid|compliant] [course=flat|stairs|...] [seconds=5]
//               [threads=2] [turnover_from=2] [offset=paper|authors] [collision=bullet|dart|fcl]
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace {

using namespace qdmeta;

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{{"count", "200"}, {"seed", "2"},    {"legs", "rigid"}, {"course", "flat"},
                                          {"seconds", "5"}, {"threads", "2"}, {"turnover_from", "2"},
                                          {"offset", "paper"}, {"collision", "bullet"}};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    if (eq == std::string::npos || !args.contains(a.substr(0, eq))) {
      fmt::print(stderr, "rhex_sanity: bad argument '{}' (key=value, keys: count seed legs course seconds threads "
                         "turnover_from offset collision)\n", a);
      return 2;
    }
    args[a.substr(0, eq)] = a.substr(eq + 1);
  }
  try {
    const Index count = std::stoll(args["count"]);
    RhexParams p;
    p.episode.legs = enum_from_string(rhex::kLegModelNames, "legs", args["legs"]);
    p.episode.duration = std::stod(args["seconds"]);
    p.episode.turnover_from = std::stod(args["turnover_from"]);
    p.stance_offset = enum_from_string(rhex::kStanceOffsetNames, "offset", args["offset"]);
    p.episode.collision = enum_from_string(rhex::kCollisionKindNames, "collision", args["collision"]);
    const auto course = enum_from_string(rhex::kObstacleCourseNames, "course", args["course"]);
    const RhexTask task(p);
    Rng rng(std::stoull(args["seed"]));
    RowMatrix g(count, rhex::kGenes);
    for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
    std::vector<rhex::EpisodeResult> results(static_cast<std::size_t>(count));
    auto evaluator = make_evaluator(std::stoi(args["threads"]));
    evaluator->parallel_for(count, [&](Index i) {
      rhex::EpisodeResult r = task.episode(g.row(i).data(), rhex::RhexEnvironment::obstacle(course));
      r.trajectory.clear();
      results[static_cast<std::size_t>(i)] = std::move(r);
    });
    int turned = 0, unsettled = 0, tilt45 = 0, tilt60 = 0, tilt80 = 0;
    std::vector<double> tilts, distances;
    for (const auto& r : results) {
      turned += r.turned_over;
      unsettled += r.dead && !r.turned_over;
      const double deg = r.max_tilt * 180.0 / 3.141592653589793;
      tilt45 += deg >= 45.0;
      tilt60 += deg >= 60.0;
      tilt80 += deg >= 80.0;
      tilts.push_back(deg);
      if (!r.dead) distances.push_back(r.fitness);
    }
    double mean = 0.0;
    for (double d : distances) mean += d / static_cast<double>(std::max<std::size_t>(1, distances.size()));
    const auto tripod = rhex::tripod_genes();
    const rhex::EpisodeResult reference = task.episode(tripod.data(), rhex::RhexEnvironment::obstacle(course));
    fmt::print("{} random controllers, seed {}, legs {}, stance offset {}, collision {}, course {}, {} s, turnover "
               "checked from {} s:\n", count, args["seed"], args["legs"], args["offset"], args["collision"],
               args["course"], args["seconds"], args["turnover_from"]);
    fmt::print("  tripod gait: {} m{}, max tilt {:.1f} deg\n", reference.fitness, reference.dead ? " (dead)" : "",
               reference.max_tilt * 180.0 / 3.141592653589793);
    fmt::print("  dead {} ({} turned over, {} never settled)\n", turned + unsettled, turned, unsettled);
    fmt::print("  max tilt (deg): median {:.1f}, 90% {:.1f}, 99% {:.1f}, max {:.1f}; >=45: {}, >=60: {}, >=80: {}\n",
               quantile(tilts, 0.5), quantile(tilts, 0.9), quantile(tilts, 0.99), quantile(tilts, 1.0), tilt45, tilt60,
               tilt80);
    fmt::print("  distance of the living (m): mean {:.3f}, median {:.3f}, max {:.3f}\n", mean, quantile(distances, 0.5),
               quantile(distances, 1.0));
  } catch (const std::exception& e) {
    fmt::print(stderr, "rhex_sanity: {}\n", e.what());
    return 2;
  }
  return 0;
}
