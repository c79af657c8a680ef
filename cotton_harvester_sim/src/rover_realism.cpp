// The rover simulation's `datasheet` side (RoverSimParams::realism): the row's plants as bodies (bolls on breaking
// springs, springy leaves), the day's light on the camera image and the ZED's passive-stereo depth.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

namespace {

bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

}  // namespace

void RoverSim::setupDatasheet() {
  const mjModel* m = model_.get();
  texture_.assign(m->ngeom, 0.0f);
  for (int g = 0; g < m->ngeom; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    if (name) texture_[g] = thorvald_sim::cottonGeomTexture(name);
  }
  for (BollTruth& b : bolls_) {
    b.body = m->geom_bodyid[b.geom];
    for (int g = 0; g < m->ngeom; ++g) {
      const char* name = mj_id2name(m, mjOBJ_GEOM, g);
      if (m->geom_bodyid[g] == b.body && name && contains(name, "_lobe"))
        geom_boll_[g] = geom_boll_[b.geom];  // the lobes are the boll as the camera sees it; bracts are not
    }
  }
  for (int j = 0; j < m->njnt; ++j) {
    const char* name = mj_id2name(m, mjOBJ_JOINT, j);
    if (name && m->jnt_type[j] == mjJNT_HINGE && contains(name, "_leaf")) leaf_joints_.push_back(j);
  }
  std::mt19937 day_rng(params_.seed * 7919u + 17u);  // its own stream: the camera noise's draws stay as they are
  daylight_ = thorvald_sim::randomDaylight(day_rng);
}

void RoverSim::setVacuum(bool on) { vacuum_ = on; }

void RoverSim::updateBollBodies() {
  mjModel* m = model_.get();
  const double limit =
      params_.parts.knock_off ? params_.row.realism.boll_break_force : std::numeric_limits<double>::infinity();
  for (BollTruth& b : bolls_) {
    if (b.body < 0 || b.captured) continue;
    b.centre = Eigen::Map<const Eigen::Vector3d>(data_->xpos + 3 * b.body);
    if (b.knocked_off) continue;
    const int j0 = m->body_jntadr[b.body];
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a) force[a] = m->jnt_stiffness[j0 + a] * data_->qpos[m->jnt_qposadr[j0 + a]];
    if (force.norm() <= limit) continue;
    b.knocked_off = true;  // the peduncle breaks: the boll falls free
    for (int a = 0; a < 3; ++a) m->jnt_stiffness[j0 + a] = 0.0;
  }
}

void RoverSim::hideBoll(const BollTruth& b) {
  mjModel* m = model_.get();
  if (b.body < 0) {
    m->geom_rgba[4 * b.geom + 3] = 0.0f;  // the renderer leaves invisible geoms out
    return;
  }
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] != b.body) continue;
    m->geom_rgba[4 * g + 3] = 0.0f;
    m->geom_contype[g] = m->geom_conaffinity[g] = 0;
  }
  const int j0 = m->body_jntadr[b.body];
  for (int a = 0; a < 3; ++a) m->jnt_stiffness[j0 + a] = params_.row.realism.boll_stiffness;  // gone: held still
}

int RoverSim::bollOfGeom(int geom) const {
  return geom >= 0 && geom < static_cast<int>(geom_boll_.size()) ? geom_boll_[geom] : -1;
}

int RoverSim::bollsKnockedOff() const {
  return static_cast<int>(
      std::count_if(bolls_.begin(), bolls_.end(), [](const BollTruth& b) { return b.knocked_off; }));
}

void RoverSim::datasheetCamera(const thorvald_sim::RenderedView& view, const thorvald_sim::SensorPose& pose,
                               const thorvald_sim::Intrinsics& k, thorvald_sim::ColorImage* rgb,
                               std::vector<float>* depth_z) {
  // The sun's view of the camera's footprint on the ground (the rover casts no shadow: left out).
  const Eigen::Vector3d ahead = pose.rotation.col(2);
  const double to_ground =
      ahead.z() < -1e-3 ? (pose.origin.z() - row_truth_.plant_bases.front().z()) / -ahead.z() : 2.0;
  const Eigen::Vector3d centre = pose.origin + to_ground * ahead;
  const bool shadows = params_.parts.shadows && daylight_.sunny;
  // Rendered again only when the camera leaves the region it covers, the plants move or the day changes.
  const thorvald_sim::ShadowMap* shadow =
      shadows ? &shadows_.get(renderer_.get(), model_.get(), data_.get(), daylight_, centre, 2.1, 720, rear_body_)
              : nullptr;
  if (params_.parts.daylight) thorvald_sim::shadeDaylight(view, pose, k, daylight_, shadow, texture_, rgb);
  if (!params_.parts.passive_stereo) {
    depth_z->clear();  // the caller measures ideal's active-stereo depth instead
    return;
  }
  true_depth_.resize(view.depth_m.size());
  for (size_t i = 0; i < view.depth_m.size(); ++i) {
    const float z = view.depth_m[i];
    true_depth_[i] = std::isfinite(z) && z >= 0.3f && z <= 20.0f ? z : std::nanf("");
  }
  thorvald_sim::passiveStereoDepth(true_depth_, rgb->rgb, view.width, view.height, k.fx, params_.stereo, rng_, depth_z,
                                   &stereo_scratch_);
}

}  // namespace sim
}  // namespace cotton_harvester
