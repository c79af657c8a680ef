#include "thorvald_sim/simulation.h"

#include <algorithm>
#include <cmath>

namespace thorvald_sim {

double BodyState::yaw() const {
  const Eigen::Vector3d x = orientation * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

Simulation::Simulation(const std::string& scene_xml, const std::vector<RobotSpawn>& robots)
    : model_(compileXml(scene_xml, "scene")), data_(mj_makeData(model_.get())) {
  for (const auto& r : robots) {
    RobotHandle h;
    h.name = r.name;
    h.root_link = r.root_link;
    h.root_body = mj_name2id(model_.get(), mjOBJ_BODY, r.root_link.c_str());
    if (h.root_body < 0) throw ModelError("robot " + r.name + ": no body " + r.root_link + " in the scene");
    const int jnt = model_->body_jntadr[h.root_body];
    if (jnt < 0 || model_->jnt_type[jnt] != mjJNT_FREE)
      throw ModelError("robot " + r.name + ": " + r.root_link + " does not move freely");
    h.qpos_adr = model_->jnt_qposadr[jnt];
    h.qvel_adr = model_->jnt_dofadr[jnt];
    robots_.push_back(h);
  }
  // Wheel servos are joint damping kv (implicit) plus a motor kv * ctrl: the torque kv (ctrl - qvel) stays within
  // the limit when ctrl is kept within qvel +- limit / kv.
  const mjModel* m = model_.get();
  limited_of_actuator_.assign(m->nu, -1);
  for (int a = 0; a < m->nu && m->nuser_actuator > 0; ++a) {
    const double limit = m->actuator_user[a * m->nuser_actuator];
    if (!(limit > 0.0) || m->actuator_trntype[a] != mjTRN_JOINT || m->actuator_gaintype[a] != mjGAIN_FIXED) continue;
    const double kv = m->actuator_gear[6 * a];
    if (!(kv > 0.0)) continue;
    limited_of_actuator_[a] = static_cast<int>(limited_.size());
    limited_.push_back({a, m->jnt_dofadr[m->actuator_trnid[2 * a]], kv, limit, 0.0});
  }
  mj_forward(model_.get(), data_.get());
}

void Simulation::step(int steps) {
  for (int i = 0; i < steps; ++i) {
    for (const auto& w : limited_) {
      const double v = data_->qvel[w.dof], band = w.torque_max / w.kv;
      data_->ctrl[w.actuator] = std::min(std::max(w.target, v - band), v + band);
    }
    mj_step(model_.get(), data_.get());
    bool bad = data_->warning[mjWARN_BADQACC].number > 0;
    for (int k = 0; k < model_->nq && !bad; ++k) bad = !std::isfinite(data_->qpos[k]);
    if (bad) {
      ++divergences_;
      reset(true);
    }
  }
}

void Simulation::reset(bool keep_time) {
  const double t = data_->time;
  mj_resetData(model_.get(), data_.get());
  if (keep_time) data_->time = t;
  for (auto& w : limited_) w.target = 0.0;
  mj_forward(model_.get(), data_.get());
}

int Simulation::actuatorOfJoint(const std::string& joint_name) const {
  const int j = mj_name2id(model_.get(), mjOBJ_JOINT, joint_name.c_str());
  if (j < 0) return -1;
  for (int a = 0; a < model_->nu; ++a)
    if (model_->actuator_trntype[a] == mjTRN_JOINT && model_->actuator_trnid[2 * a] == j) return a;
  return -1;
}

bool Simulation::setTarget(int actuator, double value) {
  if (actuator < 0 || actuator >= model_->nu || !std::isfinite(value)) return false;
  data_->ctrl[actuator] = value;
  if (limited_of_actuator_[actuator] >= 0) limited_[limited_of_actuator_[actuator]].target = value;
  return true;
}

double Simulation::target(int actuator) const {
  if (actuator < 0 || actuator >= model_->nu) return 0.0;
  const int w = limited_of_actuator_[actuator];
  return w >= 0 ? limited_[w].target : data_->ctrl[actuator];
}

bool Simulation::jointState(const std::string& joint_name, double* position, double* velocity) const {
  const int j = mj_name2id(model_.get(), mjOBJ_JOINT, joint_name.c_str());
  if (j < 0 || model_->jnt_type[j] == mjJNT_FREE || model_->jnt_type[j] == mjJNT_BALL) return false;
  if (position) *position = data_->qpos[model_->jnt_qposadr[j]];
  if (velocity) *velocity = data_->qvel[model_->jnt_dofadr[j]];
  return true;
}

BodyState Simulation::robotState(size_t i) const {
  const RobotHandle& h = robots_.at(i);
  BodyState s;
  const mjtNum* q = data_->qpos + h.qpos_adr;
  s.position = Eigen::Vector3d(q[0], q[1], q[2]);
  s.orientation = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).normalized();
  // Free joint velocities: linear in the world frame, angular in the body frame.
  const mjtNum* v = data_->qvel + h.qvel_adr;
  s.linear_body = s.orientation.conjugate() * Eigen::Vector3d(v[0], v[1], v[2]);
  s.angular_body = Eigen::Vector3d(v[3], v[4], v[5]);
  return s;
}

bool Simulation::bodyPose(const std::string& body, Eigen::Vector3d* pos, Eigen::Quaterniond* q) const {
  const int b = mj_name2id(model_.get(), mjOBJ_BODY, body.c_str());
  if (b < 0) return false;
  if (pos) *pos = Eigen::Vector3d(data_->xpos[3 * b], data_->xpos[3 * b + 1], data_->xpos[3 * b + 2]);
  if (q)
    *q = Eigen::Quaterniond(data_->xquat[4 * b], data_->xquat[4 * b + 1], data_->xquat[4 * b + 2],
                            data_->xquat[4 * b + 3]);
  return true;
}

}  // namespace thorvald_sim
