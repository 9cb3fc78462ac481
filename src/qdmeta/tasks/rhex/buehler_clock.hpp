#pragma once
// The RHex gait controller (docs/specification.md, RHex): one Buehler clock per leg turns time into a hip
// target angle, and a PI servo turns the target into a hip torque. DART-free, so it is tested
// against hand-computed values without a simulator.
#include <array>

#include "qdmeta/core/params.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta::rhex {

inline constexpr int kLegs = 6;
inline constexpr int kGenes = 24;

// How far a stance offset gene moves the stance window (docs/fidelity.md, "Stance offset"):
// the paper's (g - 0.5) pi / 2, in [-pi/4, pi/4], or the authors' code, which added it once per
// leg inside a loop over the six legs: 6 (g - 0.5) pi / 2, in [-1.5 pi, 1.5 pi].
enum class StanceOffset { kPaper, kAuthors };
inline constexpr EnumNames<StanceOffset, 2> kStanceOffsetNames{
    {{StanceOffset::kPaper, "paper"}, {StanceOffset::kAuthors, "authors"}}};
inline constexpr double stance_offset_factor(StanceOffset s) { return s == StanceOffset::kAuthors ? 6.0 : 1.0; }

// The clock parameters decoded from 24 genes in [0, 1].
struct GaitParams {
  double period = 1.0;                      // T = 1 - 0.67 g0, in [0.33, 1] s
  std::array<double, kLegs> duty{};         // d_i = g_{1+i}
  std::array<double, kLegs> stance_angle{}; // phi_s = pi g_{7+i}
  std::array<double, kLegs> stance_offset{};// (g_{13+i} - 0.5) pi / 2 x stance_offset_factor
  std::array<double, kLegs> phase_offset{}; // 0 for leg 0, g_{18+i} T / 2 for legs 1..5
};

// A hand-set reference gait: alternating tripods (legs 0, 2, 4 and 1, 3, 5), duty 0.5, stance
// angle 0.35 pi, no stance offset; `period_gene` is g0 (T = 1 - 0.67 g0). For the tests, the
// benchmarks and the physics sanity checks.
std::array<Real, kGenes> tripod_genes(Real period_gene = 0.5f);

// Snaps a gene to the grid {0, step, ..., 1} (the paper's discretisation, step 0.025).
double discretise_gene(double gene, double step);

// Decodes genes (already discretised by the caller if wanted).
GaitParams decode_gait(const double* genes, StanceOffset offset = StanceOffset::kPaper);

// Target hip angle of `leg` at time t (s): stance sweeps [-phi_s/2, phi_s/2] in d T, swing the
// remaining 2 pi - phi_s in (1 - d) T, plus one full turn per elapsed period, plus the offset.
double target_angle(const GaitParams& gait, int leg, double t);

// Brings a monotonically growing target angle within reach of the measured (unbounded) hip
// angle, following the authors' rule: count whole turns the target is ahead, drop them, and
// add one turn back if the leg is more than 3 pi / 2 ahead of the target. `turns` is the
// leg's persistent counter c_i.
double unwrap_target(double target, double measured, int& turns);

// PI servo (Kp = Ki = 15, Kd = 0), integral clamped to +-pi, torque clamped to +-4 N m.
struct ServoParams {
  double kp = 15.0;
  double ki = 15.0;
  double integral_limit = 3.141592653589793;
  double torque_limit = 4.0;
};

class PiServo {
 public:
  PiServo() = default;
  explicit PiServo(ServoParams params) : params_(params) {}
  // Torque for this control step of length dt.
  double torque(double target, double measured, double dt);
  void reset() { integral_ = 0.0; }
  double integral() const { return integral_; }

 private:
  ServoParams params_;
  double integral_ = 0.0;
};

}  // namespace qdmeta::rhex
