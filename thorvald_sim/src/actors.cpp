#include "thorvald_sim/actors.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace thorvald_sim {

namespace {

double unitDraw(std::mt19937& rng) { return rng() / 4294967296.0; }

/// The random walk as a looping path: waypoints with their pauses, back to the start at the end.
std::vector<ActorWaypoint> drawWalk(const ActorSpec& s, double horizon_s) {
  std::mt19937 rng(s.seed);
  auto point = [&]() {
    const double x = s.region[0] + unitDraw(rng) * (s.region[1] - s.region[0]);
    return ActorWaypoint{x, s.region[2] + unitDraw(rng) * (s.region[3] - s.region[2]), 0.0};
  };
  std::vector<ActorWaypoint> path{point()};
  while (path.back().t < horizon_s) {
    ActorWaypoint stand = path.back();
    stand.t += s.pause_s;
    ActorWaypoint next = point();
    next.t = stand.t + std::hypot(next.x - stand.x, next.y - stand.y) / s.speed_mps;
    path.push_back(stand);
    path.push_back(next);
  }
  ActorWaypoint home = path.front();
  home.t = path.back().t + std::hypot(home.x - path.back().x, home.y - path.back().y) / s.speed_mps;
  path.push_back(home);
  return path;
}

void check(const ActorSpec& s) {
  const std::string who = "actor '" + s.name + "': ";
  if (s.name.empty()) throw std::invalid_argument("actor without a name");
  if (s.random_walk) {
    if (!(s.region[1] > s.region[0] && s.region[3] > s.region[2]))
      throw std::invalid_argument(who + "region must be [x_min, x_max, y_min, y_max] with min < max");
    if (!(s.speed_mps > 0.0 && s.speed_mps < 10.0)) throw std::invalid_argument(who + "speed must lie in (0, 10) m/s");
    if (!(s.pause_s >= 0.0)) throw std::invalid_argument(who + "pause must be at least 0 s");
  } else {
    if (s.path.empty()) throw std::invalid_argument(who + "needs a path [[x, y, t], ...] or a random_walk region");
    for (size_t k = 1; k < s.path.size(); ++k)
      if (!(s.path[k].t > s.path[k - 1].t))
        throw std::invalid_argument(who + "path times must increase (waypoint " + std::to_string(k) + ")");
  }
  if (!(s.radius_m > 0.0 && s.height_m > 2.0 * s.radius_m && s.length_m > 0.0))
    throw std::invalid_argument(who + "needs radius > 0, height > 2 radius, length > 0");
  if (!(s.trigger_radius_m >= 0.0 && s.trigger_radius_m < 1e3 && std::isfinite(s.trigger_x) &&
        std::isfinite(s.trigger_y)))
    throw std::invalid_argument(who + "trigger needs a finite point and a radius in [0, 1000) m");
}

}  // namespace

ActorScripts::ActorScripts(std::vector<ActorSpec> specs, double walk_horizon_s) : specs_(std::move(specs)) {
  for (size_t i = 0; i < specs_.size(); ++i) {
    check(specs_[i]);
    for (size_t j = 0; j < i; ++j)
      if (specs_[j].name == specs_[i].name) throw std::invalid_argument("actor '" + specs_[i].name + "' twice");
    if (specs_[i].random_walk) {
      specs_[i].path = drawWalk(specs_[i], walk_horizon_s);
      specs_[i].loop = true;
    }
  }
}

ActorPose ActorScripts::poseAt(size_t i, double t) const {
  const std::vector<ActorWaypoint>& p = specs_.at(i).path;
  const double t0 = p.front().t, t1 = p.back().t;
  if (specs_[i].loop && t1 > t0 && t > t1) t = t0 + std::fmod(t - t0, t1 - t0);
  // The segment holding t: p[k] .. p[k + 1] (k = 0 before the start, the last one after the end).
  const auto after = std::upper_bound(p.begin(), p.end(), t, [](double v, const ActorWaypoint& w) { return v < w.t; });
  const size_t k1 = std::min<size_t>(std::max<long>(1, after - p.begin()), p.size() - 1);
  const size_t k0 = p.size() > 1 ? k1 - 1 : 0;
  const ActorWaypoint &a = p[k0], &b = p[std::min(k1, p.size() - 1)];
  const double s = b.t > a.t ? std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0) : 0.0;
  ActorPose pose;
  pose.x = a.x + s * (b.x - a.x);
  pose.y = a.y + s * (b.y - a.y);
  // Heading: along the latest segment that moved, up to this one.
  for (size_t k = k1; k >= 1 && k < p.size(); --k) {
    const double dx = p[k].x - p[k - 1].x, dy = p[k].y - p[k - 1].y;
    if (std::hypot(dx, dy) > 1e-9) {
      pose.yaw = std::atan2(dy, dx);
      break;
    }
  }
  return pose;
}

std::vector<ActorPose> ActorClocks::advance(double t, const RobotGap& gap_to_robots) {
  if (!started_) {
    std::fill(clock_.begin(), clock_.end(), t);
    for (size_t i = 0; i < clock_.size(); ++i)  // a triggered script starts at its beginning whenever it is set off
      if (scripts_.spec(i).trigger_radius_m > 0.0) clock_[i] = std::min(t, scripts_.spec(i).path.front().t);
    start_ = clock_;
    last_t_ = t;
    started_ = true;
  }
  const double dt = std::max(0.0, t - last_t_);
  last_t_ = t;
  std::vector<ActorPose> poses;
  for (size_t i = 0; i < clock_.size(); ++i) {
    const ActorSpec& spec = scripts_.spec(i);
    const double r = spec.radius_m;
    if (!running(i)) {
      triggered_[i] = gap_to_robots && gap_to_robots(spec.trigger_x, spec.trigger_y) < spec.trigger_radius_m;
      if (!triggered_[i]) {
        poses.push_back(scripts_.poseAt(i, clock_[i]));
        continue;
      }
    }
    if (back_left_[i] > 0.0) {  // giving way: back along the path, unless that walks into a robot too
      const double step = std::min({dt, back_left_[i], clock_[i] - start_[i]});  // >= 0: the clock never precedes start
      const ActorPose here = scripts_.poseAt(i, clock_[i]), back = scripts_.poseAt(i, clock_[i] - step);
      const double gap_back = gap_to_robots ? gap_to_robots(back.x, back.y) : 0.0;
      const bool free = !gap_to_robots || gap_back - r >= clearance_m_ || gap_back >= gap_to_robots(here.x, here.y);
      if (step > 0.0 && free) {
        clock_[i] -= step;
        back_left_[i] -= dt;
        poses.push_back(back);
        continue;
      }
      back_left_[i] = 0.0;  // at the start of the script, or hemmed in: on as before
    }
    const ActorPose now = scripts_.poseAt(i, clock_[i]), next = scripts_.poseAt(i, clock_[i] + dt);
    bool wait = false;
    if (gap_to_robots) {
      const double gap_next = gap_to_robots(next.x, next.y) - r, gap_now = gap_to_robots(now.x, now.y) - r;
      wait = gap_next < clearance_m_ && gap_next < gap_now - 1e-9;
    }
    if (wait) {
      waited_[i] += dt;
      standing_[i] += dt;
      if (give_way_s_ > 0.0 && standing_[i] >= give_way_s_) {
        standing_[i] = 0.0;
        back_left_[i] = step_back_s_;
      }
      poses.push_back(now);
    } else {
      standing_[i] = 0.0;
      clock_[i] += dt;
      poses.push_back(next);
    }
  }
  return poses;
}

std::string actorBodyName(const std::string& actor_name) { return "actor_" + actor_name; }

std::string actorBodies(const ActorScripts& actors, const std::function<double(double, double)>& floor_z) {
  std::ostringstream out;
  out.precision(9);
  for (size_t i = 0; i < actors.size(); ++i) {
    const ActorSpec& s = actors.spec(i);
    const ActorPose p = actors.poseAt(i, 0.0);
    const std::string name = actorBodyName(s.name);
    out << "<body name=\"" << name << "\" mocap=\"true\" pos=\"" << p.x << " " << p.y << " " << floor_z(p.x, p.y)
        << "\" euler=\"0 0 " << p.yaw << "\">";
    if (s.kind == ActorKind::kPerson)
      out << "<geom name=\"" << name << "\" type=\"capsule\" size=\"" << s.radius_m << " "
          << 0.5 * s.height_m - s.radius_m << "\" pos=\"0 0 " << 0.5 * s.height_m << "\" rgba=\"0.8 0.45 0.2 1\"/>";
    else
      out << "<geom name=\"" << name << "\" type=\"box\" size=\"" << 0.5 * s.length_m << " " << s.radius_m << " "
          << 0.5 * s.height_m << "\" pos=\"0 0 " << 0.5 * s.height_m << "\" rgba=\"0.5 0.5 0.55 1\"/>";
    out << "</body>\n";
  }
  return out.str();
}

}  // namespace thorvald_sim
