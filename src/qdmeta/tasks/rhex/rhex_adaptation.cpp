#include "qdmeta/tasks/rhex/rhex_adaptation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/evaluator.hpp"

namespace qdmeta {

RhexAdaptationTests::RhexAdaptationTests(std::string name, RhexTask task, std::vector<rhex::RhexEnvironment> environments)
    : name_(std::move(name)), task_(std::move(task)), environments_(std::move(environments)) {
  if (environments_.empty()) throw InputError(fmt::format("test '{}' has no environments", name_));
  for (const auto& e : environments_) e.validate();
}

void RhexAdaptationTests::score(Index test, const RowMatrix& genotypes, Evaluator& evaluator, std::span<double> out) const {
  if (test < 0 || test >= count()) throw Error(fmt::format("test '{}': environment {} out of range [0, {})", name_, test, count()));
  if (genotypes.cols() != rhex::kGenes)
    throw Error(fmt::format("test '{}': RHex genotypes have {} genes, given {}", name_, rhex::kGenes, genotypes.cols()));
  if (static_cast<Index>(out.size()) != genotypes.rows()) throw Error("test scores: output size differs from rows");
  const rhex::RhexEnvironment& env = environments_[static_cast<std::size_t>(test)];
  // Each episode builds its own world from the const task, so rows may run concurrently.
  evaluator.parallel_for(genotypes.rows(), [&](Index r) {
    const rhex::EpisodeResult result = task_.episode(genotypes.row(r).data(), env);
    out[static_cast<std::size_t>(r)] = result.dead ? 0.0 : result.fitness;
  });
}

namespace {
bool contains(const std::vector<rhex::RhexEnvironment>& envs, auto&& pred) {
  return std::any_of(envs.begin(), envs.end(), pred);
}
}  // namespace

std::vector<rhex::RhexEnvironment> untrained_damage_environments(const std::vector<rhex::RhexEnvironment>& trained) {
  std::vector<rhex::RhexEnvironment> out;
  for (int t = 1; t <= 4; ++t) {
    const auto type = static_cast<rhex::DamageType>(t);
    if (contains(trained, [&](const rhex::RhexEnvironment& e) { return e.damage == type; })) continue;
    for (int leg = 0; leg < rhex::kLegs; ++leg) out.push_back(rhex::RhexEnvironment::damaged(type, leg));
  }
  return out;
}

std::vector<rhex::RhexEnvironment> untrained_course_environments(const std::vector<rhex::RhexEnvironment>& trained) {
  std::vector<rhex::RhexEnvironment> out;
  for (int c = 1; c <= 9; ++c) {
    const auto course = static_cast<rhex::ObstacleCourse>(c);
    if (contains(trained, [&](const rhex::RhexEnvironment& e) { return e.course == course; })) continue;
    out.push_back(rhex::RhexEnvironment::obstacle(course));
  }
  return out;
}

}  // namespace qdmeta
