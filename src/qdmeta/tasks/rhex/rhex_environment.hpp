#pragma once
// What the RHex robot walks in: the intact robot on flat ground, one damaged leg, or one of the
// nine obstacle courses (docs/specification.md, RHex). DART-free.
#include <string>

#include "qdmeta/core/params.hpp"

namespace qdmeta::rhex {

// Numbered as in the paper (1..4).
enum class DamageType {
  kNone = 0,
  kLegRemoval = 1,     // the leg has no body and gets no command
  kLegShortening = 2,  // the leg keeps its first 5 of 8 plates
  kBlockedHip = 3,     // the hip is locked at angle 0
  kPassiveHip = 4      // the hip is unactuated but free to swing
};
inline constexpr EnumNames<DamageType, 5> kDamageTypeNames{{{DamageType::kNone, "none"},
                                                            {DamageType::kLegRemoval, "leg-removal"},
                                                            {DamageType::kLegShortening, "leg-shortening"},
                                                            {DamageType::kBlockedHip, "blocked-hip"},
                                                            {DamageType::kPassiveHip, "passive-hip"}}};

// Courses numbered as in docs/specification.md (1..9); kFlat is the normal, unobstructed floor.
enum class ObstacleCourse {
  kFlat = 0,
  kSphere = 1,
  kStairs = 2,
  kSlope = 3,
  kRubble = 4,
  kDownUpStairs = 5,
  kManyPipes = 6,
  kDitch = 7,
  kThickPipe = 8,
  kThinPipe = 9
};
inline constexpr EnumNames<ObstacleCourse, 10> kObstacleCourseNames{{{ObstacleCourse::kFlat, "flat"},
                                                                     {ObstacleCourse::kSphere, "sphere"},
                                                                     {ObstacleCourse::kStairs, "stairs"},
                                                                     {ObstacleCourse::kSlope, "slope"},
                                                                     {ObstacleCourse::kRubble, "rubble"},
                                                                     {ObstacleCourse::kDownUpStairs, "down-up-stairs"},
                                                                     {ObstacleCourse::kManyPipes, "many-pipes"},
                                                                     {ObstacleCourse::kDitch, "ditch"},
                                                                     {ObstacleCourse::kThickPipe, "thick-pipe"},
                                                                     {ObstacleCourse::kThinPipe, "thin-pipe"}}};

struct RhexEnvironment {
  DamageType damage = DamageType::kNone;
  static constexpr IntParam kDamagedLeg{
      "task", "damaged_leg", 0, 5,
      "the damaged leg (0 rear-left, 1 middle-left, 2 front-left, 3-5 the same on the right)"};
  int leg = 0;  // the damaged leg (kDamagedLeg; docs/specification.md's numbering); ignored without damage
  ObstacleCourse course = ObstacleCourse::kFlat;

  static RhexEnvironment damaged(DamageType type, int leg) { return {type, leg, ObstacleCourse::kFlat}; }
  static RhexEnvironment obstacle(ObstacleCourse course) { return {DamageType::kNone, 0, course}; }
  std::string to_string() const;
  void validate() const;
  bool operator==(const RhexEnvironment&) const = default;
};

}  // namespace qdmeta::rhex
