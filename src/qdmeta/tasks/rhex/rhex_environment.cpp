#include "qdmeta/tasks/rhex/rhex_environment.hpp"

#include <fmt/format.h>

namespace qdmeta::rhex {

std::string RhexEnvironment::to_string() const {
  if (damage != DamageType::kNone)
    return fmt::format("{}:leg{}", enum_to_string(kDamageTypeNames, damage), leg);
  return std::string(enum_to_string(kObstacleCourseNames, course));
}

void RhexEnvironment::validate() const {
  if (damage != DamageType::kNone) require(kDamagedLeg, leg);
  if (damage != DamageType::kNone && course != ObstacleCourse::kFlat)
    throw InputError("rhex environment: a damage and an obstacle course cannot be combined");
}

}  // namespace qdmeta::rhex
