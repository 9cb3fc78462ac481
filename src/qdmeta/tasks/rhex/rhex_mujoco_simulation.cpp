// The MuJoCo engine behind the episode (rhex_simulation.hpp): the model of rhex_mjcf.cpp, compiled
// once per distinct MJCF text and shared read-only by every episode (and thread); each episode
// steps its own mjData, reset to the model's initial state, so an episode's bits do not depend on
// what ran before it or beside it. The mjData are kept per thread and model and reused (a fresh
// one costs its arena's page faults and clearing, ~1/4 of a 5-s episode). Steps are split
// (mj_step2 then mj_step1) so that between steps the body poses and contacts are those of the
// current state, as DART's after World::step.
#include <mujoco/mujoco.h>

#include <fmt/format.h>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/tasks/rhex/rhex_mjcf.hpp"
#include "qdmeta/tasks/rhex/rhex_simulation.hpp"

namespace qdmeta::rhex {
namespace {

constexpr const char* kModelFile = "rhex.xml";

mjModel* compile(const std::string& xml) {
  auto vfs = std::make_unique<mjVFS>();  // large (file names): on the heap
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), kModelFile, static_cast<int>(xml.size())) != 0)
    throw Error("MuJoCo: cannot make the RHex model's virtual file");
  const int index = mj_findFileVFS(vfs.get(), kModelFile);
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[index]));
  char error[1000] = "";
  mjModel* model = mj_loadXML(kModelFile, vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  if (model == nullptr) throw Error(fmt::format("MuJoCo could not load the RHex model: {}", error));
  return model;
}

void quiet(const char*) {}

// Models by MJCF text, compiled on first use and kept for the program's life. MuJoCo's warnings
// (printed, and appended to MUJOCO_LOG.TXT in the working directory) are silenced: the one that
// matters, a diverged state, is read from the episode's mjData (diverged()).
const mjModel* model_for(const std::string& xml) {
  // Owned, so that the models are freed when the program ends (a raw pointer left in the map
  // after its destruction is what LeakSanitizer reports as a leak).
  struct DeleteModel {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
  };
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<mjModel, DeleteModel>> models;
  const std::lock_guard lock(mutex);
  mju_user_warning = quiet;
  auto it = models.find(xml);
  if (it == models.end()) it = models.emplace(xml, std::unique_ptr<mjModel, DeleteModel>(compile(xml))).first;
  return it->second.get();
}

struct DeleteData {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using DataPtr = std::unique_ptr<mjData, DeleteData>;

// This thread's idle mjData of each model. mj_resetData restores everything mj_makeData sets
// (mj_makeData is an allocation and a reset), so a reused one steps to the same bits as a new one.
std::vector<DataPtr>& idle_data(const mjModel* m) {
  thread_local std::map<const mjModel*, std::vector<DataPtr>> idle;
  return idle[m];
}

DataPtr take_data(const mjModel* m) {
  std::vector<DataPtr>& idle = idle_data(m);
  if (idle.empty()) return DataPtr(mj_makeData(m));
  DataPtr d = std::move(idle.back());
  idle.pop_back();
  mj_resetData(m, d.get());
  return d;
}

class MujocoSimulation final : public Simulation {
 public:
  MujocoSimulation(const EpisodeSettings& settings, const RhexEnvironment& environment)
      : m_(model_for(rhex_mjcf(settings, environment))), data_(take_data(m_)), d_(data_.get()) {
    body_ = mj_name2id(m_, mjOBJ_BODY, "body");
    leg_of_body_.assign(static_cast<std::size_t>(m_->nbody), -1);
    for (int i = 0; i < kLegs; ++i) {
      hip_dof_[i] = hip_qpos_[i] = -1;
      leg_root_[i] = mj_name2id(m_, mjOBJ_BODY, leg_body_name(i, 0).c_str());
      const int joint = mj_name2id(m_, mjOBJ_JOINT, hip_joint_name(i).c_str());
      if (joint >= 0) {
        hip_dof_[i] = m_->jnt_dofadr[joint];
        hip_qpos_[i] = m_->jnt_qposadr[joint];
      }
      const DamageType damage = environment.leg == i ? environment.damage : DamageType::kNone;
      actuated[i] = damage == DamageType::kNone || damage == DamageType::kLegShortening;
    }
    // Every body below a leg's root belongs to that leg.
    for (int b = 0; b < m_->nbody; ++b)
      for (int i = 0; i < kLegs; ++i)
        if (leg_root_[i] >= 0 && (b == leg_root_[i] || (b > 0 && leg_of_body_[m_->body_parentid[b]] == i)))
          leg_of_body_[b] = i;
    for (int g = 0; g < m_->ngeom; ++g) {
      const int leg = leg_of_body_[m_->geom_bodyid[g]];
      if (leg >= 0) ++leg_plates[leg];
    }
    for (int b = 0; b < m_->nbody; ++b)
      if (leg_of_body_[b] >= 0) ++leg_bodies[leg_of_body_[b]];
    mj_step1(m_, d_);
  }
  ~MujocoSimulation() override { idle_data(m_).push_back(std::move(data_)); }
  MujocoSimulation(const MujocoSimulation&) = delete;
  MujocoSimulation& operator=(const MujocoSimulation&) = delete;

  void step() override {
    mj_step2(m_, d_);
    mj_step1(m_, d_);
    // Full contact or constraint buffers drop contacts silently: a model limit to raise
    // (rhex_mjcf.cpp's <size>), never an outcome.
    if (d_->warning[mjWARN_CONTACTFULL].number > 0 || d_->warning[mjWARN_CNSTRFULL].number > 0)
      throw Error(fmt::format("MuJoCo's contact buffers are full ({} contacts): raise nconmax / njmax in rhex_mjcf.cpp",
                              d_->ncon));
  }
  bool diverged() const override { return d_->warning[mjWARN_BADQACC].number > 0; }
  Eigen::Isometry3d body_pose() const override {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = rotation(body_);
    t.translation() = Eigen::Vector3d(d_->xpos[3 * body_], d_->xpos[3 * body_ + 1], d_->xpos[3 * body_ + 2]);
    return t;
  }
  Eigen::Vector3d com_velocity() const override {
    mj_subtreeVel(m_, d_);
    const mjtNum* v = d_->subtree_linvel + 3 * body_;
    return {v[0], v[1], v[2]};
  }
  bool has_hip(int leg) const override { return hip_dof_[leg] >= 0; }
  double hip_angle(int leg) const override { return d_->qpos[hip_qpos_[leg]]; }
  void set_hip_torque(int leg, double torque) override { d_->qfrc_applied[hip_dof_[leg]] = torque; }
  Eigen::Matrix3d leg_rotation(int leg) const override { return rotation(leg_root_[leg]); }
  std::int64_t contact_count() const override { return d_->ncon; }
  std::array<bool, kLegs> legs_touching() const override {
    std::array<bool, kLegs> touching{};
    for (int c = 0; c < d_->ncon; ++c)
      for (const int geom : {d_->contact[c].geom1, d_->contact[c].geom2}) {
        const int leg = leg_of_body_[m_->geom_bodyid[geom]];
        if (leg >= 0) touching[leg] = true;
      }
    return touching;
  }

 private:
  Eigen::Matrix3d rotation(int body) const {
    return Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>>(d_->xmat + 9 * body);
  }

  const mjModel* m_;
  DataPtr data_;
  mjData* d_;
  int body_ = 0;
  std::array<int, kLegs> hip_dof_{}, hip_qpos_{}, leg_root_{};
  std::vector<int> leg_of_body_;
};

}  // namespace

std::unique_ptr<Simulation> make_mujoco_simulation(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  return std::make_unique<MujocoSimulation>(settings, environment);
}

}  // namespace qdmeta::rhex
