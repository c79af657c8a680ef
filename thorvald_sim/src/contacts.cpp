#include "thorvald_sim/contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>

namespace thorvald_sim {

namespace {

std::string nameOf(const mjModel* m, mjtObj type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? n : std::string();
}

bool isWheel(const std::string& body) {
  static const std::regex re("(.*/)?(wheel_link[0-9]+|caster[0-9]+_wheel.*|passive_wheel[0-9]+.*)");
  return std::regex_match(body, re);
}

bool isGround(const std::string& geom) {
  static const std::regex re("(row_ground|headland_floor|headland_bump|floor|rail|rusty_rail|hose).*");
  return std::regex_match(geom, re);
}

}  // namespace

ContactMonitor::ContactMonitor(const mjModel* model, const std::vector<std::pair<int, std::string>>& robot_roots)
    : m_(model), robot_of_body_(model->nbody, -1), wheel_body_(model->nbody, 0), ground_geom_(model->ngeom, 0) {
  for (size_t r = 0; r < robot_roots.size(); ++r) robot_names_.push_back(robot_roots[r].second);
  for (int b = 0; b < m_->nbody; ++b) {
    for (size_t r = 0; r < robot_roots.size(); ++r)
      if (m_->body_rootid[b] == robot_roots[r].first) robot_of_body_[b] = static_cast<int>(r);
    wheel_body_[b] = robot_of_body_[b] >= 0 && isWheel(nameOf(m_, mjOBJ_BODY, b));
  }
  for (int g = 0; g < m_->ngeom; ++g) ground_geom_[g] = m_->geom_bodyid[g] == 0 && isGround(nameOf(m_, mjOBJ_GEOM, g));
}

std::string ContactMonitor::otherName(int geom) const {
  const int b = m_->geom_bodyid[geom];
  if (b == 0) {  // a world geom: its own name says what it is
    const std::string n = nameOf(m_, mjOBJ_GEOM, geom);
    return n.empty() ? "world geom " + std::to_string(geom) : n;
  }
  return nameOf(m_, mjOBJ_BODY, b);
}

std::vector<ContactEvent> ContactMonitor::update(const mjData* d) {
  for (auto& a : active_) a.second.seen = false;
  std::vector<ContactEvent> events;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.exclude != 0) continue;  // in the margin, no force
    int g[2] = {c.geom1, c.geom2};
    for (int side = 0; side < 2; ++side) {
      const int mine = g[side], other = g[1 - side];
      const int body = m_->geom_bodyid[mine], other_body = m_->geom_bodyid[other];
      const int robot = robot_of_body_[body];
      if (robot < 0) continue;
      const int other_robot = robot_of_body_[other_body];
      if (other_robot == robot) continue;                     // within one robot
      if (other_robot >= 0 && other_robot < robot) continue;  // robot against robot: reported once, by the first
      if (wheel_body_[body] && ground_geom_[other]) continue;
      const auto key = std::make_pair(body, otherName(other));
      auto it = active_.find(key);
      const Eigen::Vector3d pos(c.pos[0], c.pos[1], c.pos[2]);
      if (it == active_.end()) {
        ContactEvent e;
        e.robot = robot_names_[robot];
        e.robot_body = nameOf(m_, mjOBJ_BODY, body);
        e.other = key.second;
        e.position = pos;
        e.time = e.start_time = d->time;
        events.push_back(e);
        ++started_;
        it = active_.emplace(key, Ongoing{e, false}).first;
      }
      it->second.seen = true;
      it->second.event.position = pos;
    }
  }
  for (auto it = active_.begin(); it != active_.end();) {
    if (it->second.seen) {
      ++it;
      continue;
    }
    ContactEvent e = it->second.event;
    e.start = false;
    e.time = d->time;
    events.push_back(e);
    it = active_.erase(it);
  }
  return events;
}

double floorGapToBodies(const mjModel* m, const mjData* d, const std::vector<int>& roots, double x, double y) {
  double best = std::numeric_limits<double>::infinity();
  for (const int root_body : roots) {
    const int root = m->body_rootid[root_body];
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->body_rootid[m->geom_bodyid[g]] != root) continue;
      const double* c = d->geom_xpos + 3 * g;
      const double* R = d->geom_xmat + 9 * g;  // row-major: local = R^T (p - c)
      const double* s = m->geom_size + 3 * g;
      double half[3];
      switch (m->geom_type[g]) {
        case mjGEOM_BOX:
        case mjGEOM_ELLIPSOID:
          half[0] = s[0], half[1] = s[1], half[2] = s[2];
          break;
        case mjGEOM_CAPSULE:
          half[0] = half[1] = s[0], half[2] = s[1] + s[0];
          break;
        case mjGEOM_CYLINDER:
          half[0] = half[1] = s[0], half[2] = s[1];
          break;
        default:
          half[0] = half[1] = half[2] = m->geom_rbound[g];
      }
      const double p[3] = {x - c[0], y - c[1], 0.0};
      double out2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double l = R[k] * p[0] + R[3 + k] * p[1] + R[6 + k] * p[2];
        const double o = std::max(0.0, std::fabs(l) - half[k]);
        out2 += o * o;
      }
      best = std::min(best, std::sqrt(out2));
    }
  }
  return best;
}

}  // namespace thorvald_sim
