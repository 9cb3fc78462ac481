#include "qdmeta/tasks/rhex/buehler_clock.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace qdmeta::rhex {

using std::numbers::pi;

std::array<Real, kGenes> tripod_genes(Real period_gene) {
  std::array<Real, kGenes> g{};
  g[0] = period_gene;
  for (int i = 1; i <= 6; ++i) g[i] = 0.5f;    // duty
  for (int i = 7; i <= 12; ++i) g[i] = 0.35f;  // stance angle
  for (int i = 13; i <= 18; ++i) g[i] = 0.5f;  // no stance offset
  g[19] = 1.0f, g[20] = 0.0f, g[21] = 1.0f, g[22] = 0.0f, g[23] = 1.0f;  // legs 1, 3, 5 half a period later
  return g;
}

double discretise_gene(double gene, double step) {
  const double steps = std::round(1.0 / step);
  return std::clamp(std::round(gene * steps) / steps, 0.0, 1.0);
}

GaitParams decode_gait(const double* g, StanceOffset offset) {
  GaitParams p;
  p.period = 1.0 - 0.67 * g[0];
  for (int i = 0; i < kLegs; ++i) {
    p.duty[i] = g[1 + i];
    p.stance_angle[i] = pi * g[7 + i];
    p.stance_offset[i] = stance_offset_factor(offset) * (g[13 + i] - 0.5) * pi / 2.0;
    p.phase_offset[i] = i == 0 ? 0.0 : g[18 + i] * p.period / 2.0;
  }
  return p;
}

double target_angle(const GaitParams& gait, int leg, double t) {
  const double period = gait.period;
  const double phase = t + gait.phase_offset[leg];
  const double cycles = std::floor(phase / period);
  const double tau = phase - cycles * period;  // in [0, T)
  const double stance = gait.stance_angle[leg];
  const double t_stance = gait.duty[leg] * period;
  double angle;
  // Guards: d = 0 has no stance (t_d = 0 would divide by zero), d = 1 has no swing.
  if (t_stance > 0.0 && tau < t_stance) {
    angle = -stance / 2.0 + (stance / t_stance) * tau;
  } else if (period - t_stance > 0.0) {
    angle = stance / 2.0 + ((2.0 * pi - stance) / (period - t_stance)) * (tau - t_stance);
  } else {
    angle = stance / 2.0;
  }
  return angle + 2.0 * pi * cycles + gait.stance_offset[leg];
}

double unwrap_target(double target, double measured, int& turns) {
  while (target - 2.0 * pi * turns - measured >= 2.0 * pi) ++turns;
  double unwrapped = target - 2.0 * pi * turns;
  if (measured - unwrapped > 1.5 * pi) unwrapped += 2.0 * pi;
  return unwrapped;
}

double PiServo::torque(double target, double measured, double dt) {
  const double error = target - measured;
  integral_ = std::clamp(integral_ + error * dt, -params_.integral_limit, params_.integral_limit);
  const double u = params_.kp * error + params_.ki * integral_;
  return std::clamp(u, -params_.torque_limit, params_.torque_limit);
}

}  // namespace qdmeta::rhex
