#include "world_truth.h"

#include <cmath>
#include <stdexcept>

#include "thorvald_sim/ActorArray.h"
#include "thorvald_sim/BodyContact.h"

namespace thorvald_sim {

namespace {

std::vector<std::pair<int, std::string>> robotRoots(const Simulation& sim) {
  std::vector<std::pair<int, std::string>> roots;
  for (size_t i = 0; i < sim.robotCount(); ++i) roots.emplace_back(sim.robot(i).root_body, sim.robot(i).name);
  return roots;
}

}  // namespace

WorldTruth::WorldTruth(ros::NodeHandle nh, Simulation& sim, ActorScripts actors,
                       std::function<double(double, double)> floor_z, const std::string& world_frame, double give_way_s)
    : sim_(sim),
      actors_(std::move(actors)),
      clocks_(actors_, 0.3, give_way_s),
      floor_z_(std::move(floor_z)),
      world_frame_(world_frame),
      contacts_(sim.model(), robotRoots(sim)) {
  for (size_t i = 0; i < actors_.size(); ++i) {
    const std::string body = actorBodyName(actors_.spec(i).name);
    const int b = mj_name2id(sim.model(), mjOBJ_BODY, body.c_str());
    if (b < 0 || sim.model()->body_mocapid[b] < 0) throw std::invalid_argument("no mocap body " + body);
    mocap_.push_back(sim.model()->body_mocapid[b]);
  }
  actors_pub_ = nh.advertise<ActorArray>("sim/actors", 10);
  contacts_pub_ = nh.advertise<BodyContact>("sim/contacts", 100);
}

void WorldTruth::moveActors(double t) {
  if (actors_.size() == 0) return;
  mjData* d = sim_.mutableData();
  std::vector<int> roots;
  for (size_t r = 0; r < sim_.robotCount(); ++r) roots.push_back(sim_.robot(r).root_body);
  const auto gap = [this, d, &roots](double x, double y) { return floorGapToBodies(sim_.model(), d, roots, x, y); };
  const std::vector<ActorPose> poses = clocks_.advance(t, gap);
  for (size_t i = 0; i < actors_.size(); ++i) {
    const ActorPose& p = poses[i];
    double* pos = d->mocap_pos + 3 * mocap_[i];
    double* q = d->mocap_quat + 4 * mocap_[i];
    pos[0] = p.x, pos[1] = p.y, pos[2] = floor_z_(p.x, p.y);
    q[0] = std::cos(0.5 * p.yaw), q[1] = 0.0, q[2] = 0.0, q[3] = std::sin(0.5 * p.yaw);
  }
}

void WorldTruth::publish(const ros::Time& now, double actor_period_s) {
  for (const ContactEvent& e : contacts_.update(sim_.data())) {
    BodyContact m;
    m.header.stamp = ros::Time(e.time);
    m.header.frame_id = world_frame_;
    m.event = e.start ? BodyContact::START : BodyContact::END;
    m.robot = e.robot;
    m.robot_body = e.robot_body;
    m.other = e.other;
    m.x = e.position.x(), m.y = e.position.y(), m.z = e.position.z();
    m.start = ros::Time(e.start_time);
    contacts_pub_.publish(m);
  }
  if (actors_.size() == 0 || now.toSec() + 1e-9 < next_actors_s_) return;
  next_actors_s_ = now.toSec() + actor_period_s;
  ActorArray msg;
  msg.header.stamp = now;
  msg.header.frame_id = world_frame_;
  const mjData* d = sim_.data();
  for (size_t i = 0; i < actors_.size(); ++i) {
    const ActorSpec& s = actors_.spec(i);
    const double* pos = d->mocap_pos + 3 * mocap_[i];
    const double* q = d->mocap_quat + 4 * mocap_[i];
    Actor a;
    a.name = s.name;
    a.kind = s.kind == ActorKind::kPerson ? "person" : "trolley";
    a.x = pos[0], a.y = pos[1], a.z = pos[2];
    a.yaw = 2.0 * std::atan2(q[3], q[0]);
    a.radius = s.radius_m, a.height = s.height_m;
    msg.actors.push_back(a);
  }
  actors_pub_.publish(msg);
}

void WorldTruth::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const {
  if (contacts_.started() == 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "no body contacts");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "robot bodies touched the world (see sim/contacts)");
  stat.add("contacts begun", contacts_.started());
  stat.add("contacts ongoing", contacts_.active());
  stat.add("actors", actors_.size());
  double waited = 0.0;
  for (size_t i = 0; i < actors_.size(); ++i) waited += clocks_.waited(i);
  stat.add("actors' time waiting for robots [s]", waited);
}

}  // namespace thorvald_sim
