#include "arm_task.hpp"

#include <qdmeta/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace arm {

ArmTask::ArmTask(int joints) : joints_(joints) {
  if (joints < 1) throw qdmeta::InputError("the arm needs at least one joint");
}

void ArmTask::evaluate(qdmeta::GenotypeView genotypes, qdmeta::EvaluationView out) const {
  const double link = 1.0 / joints_;
  for (qdmeta::Index i = 0; i < genotypes.count; ++i) {
    const qdmeta::Real* genes = genotypes.row(i);
    double mean = 0, square = 0, heading = 0, x = 0, y = 0;
    for (int j = 0; j < joints_; ++j) {
      const double angle = (genes[j] - 0.5) * 2 * std::numbers::pi;
      mean += angle;
      square += angle * angle;
      heading += angle;  // each joint turns relative to the link before it
      x += link * std::cos(heading);
      y += link * std::sin(heading);
    }
    mean /= joints_;
    out.fitness[i] = static_cast<qdmeta::Real>(-(square / joints_ - mean * mean));
    out.base_row(i)[0] = static_cast<qdmeta::Real>(std::clamp((x + 1) / 2, 0.0, 1.0));
    out.base_row(i)[1] = static_cast<qdmeta::Real>(std::clamp((y + 1) / 2, 0.0, 1.0));
    out.valid[i] = 1;
  }
}

}  // namespace arm
