// Tests of the DART-free parts of the RHex task: the Buehler clock (src/qdmeta/tasks/rhex/
// buehler_clock.*) against hand-computed angles, the unwrapping rule, the PI servo, and the two
// base-feature spaces (rhex_features.*) on hand-made records.
//
// Hand computations (leg 0, g0 = 0 -> T = 1 s; d = 0.5 -> t_d = 0.5 s; g7 = 0.5 -> phi_s = pi/2;
// g13 = 0.5 -> no stance offset):
//   stance (tau < 0.5): -pi/4 + (pi/2 / 0.5) tau = -pi/4 + pi tau
//     t = 0    -> -pi/4;  t = 0.25 -> 0
//   swing: pi/4 + ((2 pi - pi/2) / 0.5)(tau - 0.5) = pi/4 + 3 pi (tau - 0.5)
//     t = 0.5  -> pi/4;   t = 0.75 -> pi/4 + 3 pi/4 = pi
//   next period adds 2 pi: t = 1 -> -pi/4 + 2 pi = 7 pi/4; t = 1.25 -> 2 pi
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "qdmeta/tasks/rhex/buehler_clock.hpp"
#include "qdmeta/tasks/rhex/rhex_features.hpp"

namespace qdmeta::rhex {
namespace {

using std::numbers::pi;

std::array<double, kGenes> half_genes() {
  std::array<double, kGenes> g{};
  g.fill(0.5);
  return g;
}

GaitParams unit_period_gait() {
  auto g = half_genes();
  g[0] = 0.0;  // T = 1 s
  return decode_gait(g.data());
}

TEST(BuehlerClock, DecodesGenesAsSpecified) {
  auto g = half_genes();
  g[0] = 1.0;
  g[8] = 1.0;   // leg 1 stance angle pi
  g[14] = 0.0;  // leg 1 stance offset -pi/4
  g[19] = 1.0;  // leg 1 phase offset T/2
  const GaitParams p = decode_gait(g.data());
  EXPECT_DOUBLE_EQ(p.period, 0.33);
  EXPECT_DOUBLE_EQ(p.duty[3], 0.5);
  EXPECT_DOUBLE_EQ(p.stance_angle[0], pi / 2);
  EXPECT_DOUBLE_EQ(p.stance_angle[1], pi);
  EXPECT_DOUBLE_EQ(p.stance_offset[0], 0.0);
  EXPECT_DOUBLE_EQ(p.stance_offset[1], -pi / 4);
  EXPECT_DOUBLE_EQ(p.phase_offset[0], 0.0);  // leg 0 is the reference
  EXPECT_DOUBLE_EQ(p.phase_offset[1], 0.33 / 2);
  EXPECT_DOUBLE_EQ(p.phase_offset[2], 0.5 * 0.33 / 2);
  EXPECT_DOUBLE_EQ(decode_gait(half_genes().data()).period, 1.0 - 0.67 * 0.5);
}

TEST(BuehlerClock, TheAuthorsStanceOffsetIsSixTimesThePapers) {
  auto g = half_genes();
  g[13] = 0.0;   // leg 0: the lowest offset
  g[14] = 1.0;   // leg 1: the highest
  g[15] = 0.75;  // leg 2
  const GaitParams paper = decode_gait(g.data(), StanceOffset::kPaper);
  const GaitParams authors = decode_gait(g.data(), StanceOffset::kAuthors);
  EXPECT_DOUBLE_EQ(paper.stance_offset[0], -pi / 4);
  EXPECT_DOUBLE_EQ(paper.stance_offset[1], pi / 4);
  EXPECT_DOUBLE_EQ(authors.stance_offset[0], -1.5 * pi);  // the stance window anywhere on the circle
  EXPECT_DOUBLE_EQ(authors.stance_offset[1], 1.5 * pi);
  EXPECT_DOUBLE_EQ(authors.stance_offset[2], 6.0 * 0.25 * pi / 2);
  EXPECT_DOUBLE_EQ(authors.stance_offset[3], 0.0);  // gene 0.5: no offset under either
  // Nothing else changes, and the target moves by the offset alone.
  EXPECT_EQ(paper.period, authors.period);
  EXPECT_EQ(paper.stance_angle, authors.stance_angle);
  EXPECT_EQ(paper.phase_offset, authors.phase_offset);
  EXPECT_NEAR(target_angle(authors, 1, 0.2) - target_angle(paper, 1, 0.2), 1.25 * pi, 1e-12);
}

TEST(BuehlerClock, StanceAndSwingAtHandComputedTimes) {
  const GaitParams p = unit_period_gait();
  EXPECT_NEAR(target_angle(p, 0, 0.0), -pi / 4, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 0.25), 0.0, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 0.5), pi / 4, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 0.75), pi, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 1.0), 7 * pi / 4, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 1.25), 2 * pi, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 10.25), 20 * pi, 1e-9);  // one turn per period
}

TEST(BuehlerClock, StanceOffsetIsAddedOnceAndPhaseOffsetShiftsTime) {
  auto g = half_genes();
  g[0] = 0.0;
  g[13] = 1.0;  // leg 0 offset +pi/4
  g[19] = 1.0;  // leg 1 starts half a period ahead
  const GaitParams p = decode_gait(g.data());
  EXPECT_NEAR(target_angle(p, 0, 0.25), pi / 4, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 0.75), pi + pi / 4, 1e-12);
  EXPECT_NEAR(target_angle(p, 1, 0.0), pi / 4, 1e-12);  // = leg 0 (no offset) at t = 0.5
  EXPECT_NEAR(target_angle(p, 1, 0.25), pi, 1e-12);
}

TEST(BuehlerClock, DutyFactorEdgesAreGuarded) {
  auto g = half_genes();
  g[0] = 0.0;
  g[1] = 0.0;  // leg 0: no stance at all, t_d = 0
  g[2] = 1.0;  // leg 1: no swing at all
  g[19] = 0.0;  // leg 1 in phase with leg 0
  const GaitParams p = decode_gait(g.data());
  // d = 0: pure swing, pi/4 + (3 pi/2 / 1) tau.
  EXPECT_NEAR(target_angle(p, 0, 0.0), pi / 4, 1e-12);
  EXPECT_NEAR(target_angle(p, 0, 0.5), pi / 4 + 3 * pi / 4, 1e-12);
  // d = 1: pure stance, -pi/4 + (pi/2) tau.
  EXPECT_NEAR(target_angle(p, 1, 0.5), 0.0, 1e-12);
  for (double t = 0; t < 3; t += 0.01) {
    EXPECT_TRUE(std::isfinite(target_angle(p, 0, t)));
    EXPECT_TRUE(std::isfinite(target_angle(p, 1, t)));
  }
}

TEST(BuehlerClock, TargetIsContinuousAndNonDecreasing) {
  auto g = half_genes();
  g[0] = 0.3;
  g[1] = 0.2;
  g[7] = 0.9;
  const GaitParams p = decode_gait(g.data());
  double last = target_angle(p, 0, 0.0);
  for (int k = 1; k <= 2000; ++k) {
    const double a = target_angle(p, 0, k * 0.001);
    EXPECT_GE(a, last - 1e-9);
    EXPECT_LT(a - last, 0.1);  // no jumps: at most (2 pi - phi_s) / ((1 - d) T) x 1 ms ~ 0.02
    last = a;
  }
}

TEST(BuehlerClock, GenesSnapToTheGrid) {
  EXPECT_DOUBLE_EQ(discretise_gene(0.51, 0.025), 0.5);
  EXPECT_DOUBLE_EQ(discretise_gene(0.52, 0.025), 0.525);
  EXPECT_DOUBLE_EQ(discretise_gene(0.0, 0.025), 0.0);
  EXPECT_DOUBLE_EQ(discretise_gene(1.0, 0.025), 1.0);
  EXPECT_DOUBLE_EQ(discretise_gene(0.9999, 0.025), 1.0);
}

TEST(UnwrapTarget, DropsWholeTurnsAndRemembersThem) {
  int turns = 0;
  EXPECT_DOUBLE_EQ(unwrap_target(0.1, 0.0, turns), 0.1);
  EXPECT_EQ(turns, 0);
  // Three turns ahead of a leg at 0.05: c becomes 3 and the target comes back to 0.1.
  EXPECT_NEAR(unwrap_target(6 * pi + 0.1, 0.05, turns), 0.1, 1e-12);
  EXPECT_EQ(turns, 3);
  EXPECT_NEAR(unwrap_target(6 * pi + 0.2, 0.1, turns), 0.2, 1e-12);  // counter persists
  EXPECT_EQ(turns, 3);
  // Less than a turn ahead: unchanged.
  EXPECT_NEAR(unwrap_target(6 * pi + 0.1 + 2 * pi - 0.01, 0.1, turns), 0.1 + 2 * pi - 0.01, 1e-12);
  EXPECT_EQ(turns, 3);
}

TEST(UnwrapTarget, LegFarAheadGetsATurnAdded) {
  int turns = 0;
  EXPECT_NEAR(unwrap_target(0.1, 5.0, turns), 0.1 + 2 * pi, 1e-12);  // 5.0 - 0.1 > 3 pi/2
  EXPECT_NEAR(unwrap_target(0.1, 4.0, turns), 0.1, 1e-12);            // 3.9 < 3 pi/2
  EXPECT_EQ(turns, 0);
}

TEST(PiServo, ProportionalPlusIntegralWithClamps) {
  PiServo servo;
  EXPECT_NEAR(servo.torque(0.1, 0.0, 0.005), 15 * 0.1 + 15 * 0.0005, 1e-12);
  EXPECT_NEAR(servo.torque(0.1, 0.0, 0.005), 15 * 0.1 + 15 * 0.001, 1e-12);  // integral accumulates
  EXPECT_DOUBLE_EQ(servo.torque(1.0, 0.0, 0.005), 4.0);
  EXPECT_DOUBLE_EQ(servo.torque(-1.0, 0.0, 0.005), -4.0);
  servo.reset();
  servo.torque(1000.0, 0.0, 0.005);  // integral would be 5
  EXPECT_DOUBLE_EQ(servo.integral(), pi);
}

TEST(RhexFeatures, TrajectoryDifferencesAreNormalisedAndClipped) {
  std::vector<RelativePose> samples(kTrajectorySamples);
  for (int k = 0; k < kTrajectorySamples; ++k) samples[k].x = 0.525 * k;  // half the max x deviation
  samples[1].y = -1.15;                                                   // -max: 0 ...
  samples[2].y = samples[1].y;
  samples[3].x = samples[2].x + 5.0;                                      // clipped to 1
  samples[5].yaw = 3.1;
  samples[6].yaw = -3.1;  // wraps to +0.0832
  std::array<Real, kTrajectoryFeatures> out{};
  trajectory_features(samples, out.data());
  EXPECT_FLOAT_EQ(out[0], 0.75f);
  EXPECT_FLOAT_EQ(out[1], 0.0f);
  EXPECT_FLOAT_EQ(out[5 + 1], 0.5f);  // no y change in the second interval
  EXPECT_FLOAT_EQ(out[2 * 5], 1.0f);
  EXPECT_NEAR(out[5 * 5 + 4], (1.0 + (2 * pi - 6.2) / 1.27) / 2.0, 1e-6);
  EXPECT_NEAR(out[4 * 5 + 4], (1.0 + 3.1 / 1.27) / 2.0 > 1 ? 1.0 : (1.0 + 3.1 / 1.27) / 2.0, 1e-6);
  for (Real v : out) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
}

TEST(RhexFeatures, FeatureSetsAreFractionsAndNormalisedVelocities) {
  FeatureSetCounts c;
  c.samples = 10;
  c.leg_contact = {5, 10, 0, 1, 2, 3};
  for (int k = 0; k < 4; ++k) c.add_orientation({0, 0, 0, 0.1, -0.1, 0.001});  // roll>, pitch<, yaw neither
  c.velocity_sum = {10 * 0.702, 0.0, 10 * 0.03475};
  std::array<Real, kFeatureSetFeatures> out{};
  feature_set_features(c, out.data());
  const std::array<float, 15> expected{0.5f, 1.0f, 0.0f, 0.1f, 0.2f, 0.3f,   // duty factors
                                       0.4f, 0.0f, 0.0f, 0.4f, 0.0f, 0.0f,   // orientations
                                       0.5f, 0.5f, 1.0f};                    // velocities
  for (int j = 0; j < 15; ++j) EXPECT_NEAR(out[j], expected[j], 1e-6) << "feature " << j;
}

}  // namespace
}  // namespace qdmeta::rhex
