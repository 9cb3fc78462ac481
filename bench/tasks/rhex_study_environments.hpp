#pragma once
// The environments of the RHex study, in the order the comparison programs report them: flat
// ground, the four damages on one leg, then the nine obstacle courses (rhex_engines,
// rhex_crosscheck).
#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

#include "qdmeta/tasks/rhex/rhex_environment.hpp"

namespace qdmeta::bench {

inline std::vector<std::pair<std::string, rhex::RhexEnvironment>> rhex_study_environments(int leg) {
  std::vector<std::pair<std::string, rhex::RhexEnvironment>> envs{{"flat", {}}};
  for (auto d : {rhex::DamageType::kLegRemoval, rhex::DamageType::kLegShortening, rhex::DamageType::kBlockedHip,
                 rhex::DamageType::kPassiveHip})
    envs.emplace_back(fmt::format("{} leg {}", enum_to_string(rhex::kDamageTypeNames, d), leg),
                      rhex::RhexEnvironment::damaged(d, leg));
  for (const auto& [course, name] : rhex::kObstacleCourseNames)
    if (course != rhex::ObstacleCourse::kFlat) envs.emplace_back(std::string(name), rhex::RhexEnvironment::obstacle(course));
  return envs;
}

}  // namespace qdmeta::bench
