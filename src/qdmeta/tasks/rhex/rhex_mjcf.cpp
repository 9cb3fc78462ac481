// The RHex MJCF. Robot geoms collide only with the terrain (contype 1 / conaffinity 0 against the
// terrain's 0 / 1), as DART's robot has no self-collision. Contacts: friction 1 (sliding only,
// condim 3, pyramidal cone as DART's boxed LCP), no restitution. MuJoCo's soft contact is given
// DART's contact law at the same step (direct solref: stiffness, damping): damping 1 / dt stops
// the approach within a step as DART's inelastic LCP row does, and stiffness ERP / dt^2 (ERP =
// 0.01, DART's error reduction) pushes a penetration out at 2 x depth per second as DART does. The
// earlier time constant of 2 steps (stiffness 1 / (2 dt)^2, 25 x DART's) threw a robot that met a
// stone or a bar edge at speed (docs/fidelity.md, "RHex on MuJoCo"). Impedance near 1 (solimp
// 0.99-0.999: contacts nearly as hard as DART's; 0.9-0.95 let the robot bounce). Compliant legs
// (48 degrees of freedom) use MuJoCo's sparse Jacobians: ~0.7x the time, distances the same to 8
// digits (bench/README.md); rigid legs (12) stay dense, which is as fast.
#include "qdmeta/tasks/rhex/rhex_mjcf.hpp"

#include <fmt/format.h>

#include "qdmeta/tasks/rhex/rhex_course.hpp"
#include "qdmeta/tasks/rhex/rhex_geometry.hpp"

namespace qdmeta::rhex {
namespace {

// Contact buffers: sized for the worst course (rubble) with room to spare; mjData's arena, allocated
// and cleared once per episode, grows with them (4,000 rows cost ~0.1 s an episode in page faults).
constexpr int kMaxContacts = 250;

// DART's contact error reduction per step (its ContactConstraint's default ERP).
constexpr double kDartErrorReduction = 0.01;

std::string vec(const Eigen::Vector3d& v) { return fmt::format("{:.17g} {:.17g} {:.17g}", v.x(), v.y(), v.z()); }

std::string quat(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  return fmt::format("{:.17g} {:.17g} {:.17g} {:.17g}", q.w(), q.x(), q.y(), q.z());
}

std::string placement(const Eigen::Isometry3d& t) {
  return fmt::format("pos=\"{}\" quat=\"{}\"", vec(t.translation()), quat(t.linear()));
}

Eigen::Isometry3d translation(const Eigen::Vector3d& v) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = v;
  return t;
}

std::string inertial(const MassProperties& m) {
  const Eigen::Matrix3d& i = m.moment;
  return fmt::format("<inertial pos=\"{}\" mass=\"{:.17g}\" fullinertia=\"{:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\"/>\n",
                     vec(m.com), m.mass, i(0, 0), i(1, 1), i(2, 2), i(0, 1), i(0, 2), i(1, 2));
}

std::string box(const Eigen::Vector3d& size, const Eigen::Isometry3d& where, const char* cls) {
  return fmt::format("<geom class=\"{}\" type=\"box\" size=\"{}\" {}/>\n", cls, vec(size / 2.0), placement(where));
}

std::string plate(const Eigen::Isometry3d& where) {
  return box(Eigen::Vector3d(kPlateLength, kPlateWidth, kPlateThickness), where, "robot");
}

std::string hip(int leg, DamageType damage) {
  if (damage == DamageType::kBlockedHip) return "";  // the leg is welded at angle 0
  return fmt::format("<joint name=\"{}\" type=\"hinge\" axis=\"0 1 0\" damping=\"{:.17g}\"/>\n", hip_joint_name(leg),
                     kHipDamping);
}

// Plate joint k (between plates k - 1 and k) of the compliant leg: a spring-damper stepped as
// DART steps its joint springs. DART integrates a joint's spring (k) and damping (c) implicitly:
// (I + h c + h^2 k) qdd = tau - k (q - q0) - (c + h k) qd at step h (GenericJoint: h c + h^2 k
// added to the projected articulated inertia, the spring read at the next position q + h qd), and
// its contacts and limits are solved against that inertia too. Here that equation in MuJoCo's
// parts: the passive spring (stiffness, springref 0: the rest pose is the start), armature
// h c + h^2 k (in the mass matrix, so the constraint solver sees it as DART's does), and the
// damping c + h k as a velocity actuator (ctrl 0, explicit: the Euler integrator would also add
// h d to the matrix for a joint `damping` d, counting the implicit term twice). With the damping
// c alone the spring (period ~4e-5 s) diverges in the second step; as an implicit joint damping
// c + h k without armature, contacts are solved against the bare plates and the legs give way
// (every robot turned over). The limits [0, pi/64] are DART's hard limit rows with the contacts'
// error reduction (its JointLimitConstraint's defaults are its contacts'): the joints' default
// solreflimit in rhex_mjcf().
std::string plate_joint(const EpisodeSettings& settings, int leg, int k) {
  const double stiffness = plate_joint_stiffness(k), h = settings.time_step;
  return fmt::format("<joint name=\"{}\" type=\"hinge\" axis=\"0 1 0\" stiffness=\"{:.17g}\" springref=\"0\" "
                     "armature=\"{:.17g}\" limited=\"{}\" range=\"0 {:.17g}\"/>\n",
                     plate_joint_name(leg, k), stiffness, h * kPlateJointDamping + h * h * stiffness,
                     settings.plate_joint_limits ? "true" : "false", kPlateJointUpper);
}

int plates_of(int leg, const RhexEnvironment& environment) {
  if (environment.leg != leg) return kPlates;
  return environment.damage == DamageType::kLegRemoval ? 0
         : environment.damage == DamageType::kLegShortening ? kShortenedPlates : kPlates;
}

// The plate joints' damping c + h k (plate_joint above).
std::string plate_dampers(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  if (settings.legs == LegModel::kRigid) return "";
  std::string out = "<actuator>\n";
  for (int i = 0; i < kLegs; ++i)
    for (int k = 1; k < plates_of(i, environment); ++k)
      out += fmt::format("<velocity joint=\"{}\" kv=\"{:.17g}\"/>\n", plate_joint_name(i, k),
                         kPlateJointDamping + settings.time_step * plate_joint_stiffness(k));
  return out + "</actuator>\n";
}

std::string leg(const EpisodeSettings& settings, int i, const RhexEnvironment& environment) {
  const DamageType damage = environment.leg == i ? environment.damage : DamageType::kNone;
  const int plates = plates_of(i, environment);
  const Eigen::Isometry3d at_hip = translation(hip_position(i));
  if (settings.legs == LegModel::kRigid) {
    std::string out = fmt::format("<body name=\"{}\" {}>\n", leg_body_name(i, 0), placement(at_hip)) + hip(i, damage);
    std::vector<Eigen::Isometry3d> frames;
    for (int k = 0; k < plates; ++k) frames.push_back(plate_frame(k) * plate_shape_offset());
    out += inertial(plates_mass(frames));
    for (const auto& f : frames) out += plate(f);
    return out + "</body>\n";
  }
  // Compliant: plate k's body frame at its start on the arc (as DART's), each hinged to the last.
  std::string out;
  const MassProperties one = plates_mass({plate_shape_offset()});
  for (int k = 0; k < plates; ++k) {
    const Eigen::Isometry3d where = k == 0 ? at_hip * plate_frame(0) : plate_frame(k - 1).inverse() * plate_frame(k);
    out += fmt::format("<body name=\"{}\" {}>\n", leg_body_name(i, k), placement(where));
    out += k == 0 ? hip(i, damage) : plate_joint(settings, i, k);
    out += inertial(one) + plate(plate_shape_offset());
  }
  for (int k = 0; k < plates; ++k) out += "</body>\n";
  return out;
}

std::string terrain(ObstacleCourse course) {
  std::string out;
  for (const TerrainShape& s : course_shapes(course)) {
    if (s.kind == TerrainShape::Kind::kBox) out += box(s.size, s.where, "terrain");
    else out += fmt::format("<geom class=\"terrain\" type=\"sphere\" size=\"{:.17g}\" pos=\"{}\"/>\n", s.radius,
                            vec(s.where.translation()));
  }
  return out;
}

std::string robot(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  std::string out = fmt::format("<body name=\"body\" pos=\"0 0 {:.17g}\">\n<freejoint/>\n", kStartHeight);
  out += inertial(body_mass());
  out += box(Eigen::Vector3d(kBodyLength, kBodyWidth, kBodyHeight), Eigen::Isometry3d::Identity(), "robot");
  for (const double side : {1.0, -1.0})
    out += box(Eigen::Vector3d(kSpacerLength, kSpacerWidth, kBodyHeight),
               translation(spacer_position(side)), "robot");
  for (int i = 0; i < kLegs; ++i)
    if (plates_of(i, environment) > 0) out += leg(settings, i, environment);
  return out + "</body>\n";
}

// The <option> attributes of the solver options that differ from MuJoCo's defaults (none in the
// faithful setting, whose MJCF text is then what it always was).
std::string solver_options(const MujocoOptions& o) {
  const MujocoOptions defaults;
  std::string out;
  if (o.solver != defaults.solver)
    out += fmt::format(" solver=\"{}\"", o.solver == MujocoOptions::Solver::kPgs ? "PGS" : "CG");
  if (o.iterations != defaults.iterations) out += fmt::format(" iterations=\"{}\"", o.iterations);
  if (o.tolerance != defaults.tolerance) out += fmt::format(" tolerance=\"{:.17g}\"", o.tolerance);
  if (o.noslip_iterations != defaults.noslip_iterations)
    out += fmt::format(" noslip_iterations=\"{}\"", o.noslip_iterations);
  return out;
}

}  // namespace

std::string leg_body_name(int leg, int plate) { return fmt::format("leg_{}_plate_{}", leg, plate); }
std::string hip_joint_name(int leg) { return fmt::format("hip_{}", leg); }
std::string plate_joint_name(int leg, int plate) { return fmt::format("leg_{}_joint_{}", leg, plate); }

std::string rhex_mjcf(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  const double dt = settings.time_step;
  const double stiffness = kDartErrorReduction / (dt * dt), damping = 1.0 / dt;
  const std::string solref = fmt::format("{:.17g} {:.17g}", -stiffness, -damping);
  return fmt::format(R"(<mujoco model="rhex">
<compiler angle="radian" inertiafromgeom="false"/>
<option timestep="{:.17g}" gravity="0 0 -9.81" integrator="{}" cone="{}" {}{}/>
<size njmax="{}" nconmax="{}"/>
<default>
<geom friction="{:.17g} 0.005 0.0001" condim="3" solref="{}" solimp="0.99 0.999 0.001"/>
<joint solreflimit="{}" solimplimit="0.99 0.999 0.001"/>
<default class="robot"><geom contype="1" conaffinity="0"/></default>
<default class="terrain"><geom contype="0" conaffinity="1"/></default>
</default>
<worldbody>
{}{}</worldbody>
{}</mujoco>
)",
                     settings.time_step, settings.mujoco.implicit ? "implicit" : "Euler",
                     settings.mujoco.elliptic_cone ? "elliptic" : "pyramidal",
                     settings.legs == LegModel::kCompliant ? "jacobian=\"sparse\"" : "", solver_options(settings.mujoco),
                     4 * kMaxContacts, kMaxContacts, kFriction, solref, solref, terrain(environment.course),
                     robot(settings, environment),
                     plate_dampers(settings, environment));
}

}  // namespace qdmeta::rhex
