#include "headland_navigator_settings.h"

#include <algorithm>
#include <exception>

#include <thorvald_common/ros/param_reader.h>

#include "thorvald_base/ros/robot_config_params.h"
#include "thorvald_navigation/robot_footprint.h"

namespace thorvald_navigation {

Footprint makeFootprint(const std::vector<double>& flat, double padding) {
  Footprint fp;
  for (std::size_t i = 0; i + 1 < flat.size(); i += 2) {
    Eigen::Vector2d p(flat[i], flat[i + 1]);
    // Pad outwards from the polygon's centroid direction (exact for rectangles around base_link's box).
    p += Eigen::Vector2d(p.x() >= 0 ? padding : -padding, p.y() >= 0 ? padding : -padding);
    fp.polygon.push_back(p);
  }
  return fp;
}

namespace {

using R = thorvald_common::ParamRange;

void check(const std::string& problem) {
  if (!problem.empty()) throw thorvald_common::ParamError("headland_navigator: " + problem);
}

/// Frames, topics, localisation gate, footprint, obstacles, timing, costmap and planner.
void readNavigatorParams(thorvald_common::ParamReader& r, Settings* s) {
  s->global_frame = r.text("global_frame", s->global_frame);
  s->base_frame = r.text("robot_base_frame", s->base_frame);
  s->keep_out_topic = r.text("keep_out_topic", s->keep_out_topic);
  s->localization_status_topic = r.text("localization_status_topic", s->localization_status_topic);
  s->goal.gate.lost_wait_s =
      r.number("localization_lost_wait", s->goal.gate.lost_wait_s, R::aboveUpTo(0.0, 3600.0), "s");
  s->goal.gate.uncertain_wait_s =
      r.number("localization_uncertain_wait", s->goal.gate.uncertain_wait_s, R::aboveUpTo(0.0, 3600.0), "s");
  s->controller_frequency = r.number("controller_frequency", s->controller_frequency, R::aboveUpTo(0.0, 200.0), "Hz");
  s->footprint_padding = r.number("footprint_padding", s->footprint_padding, R::closed(0.0, 1.0), "m");
  s->footprint = r.numbers("footprint", s->footprint, R::closed(-20.0, 20.0), "m", 0, 200);
  s->drive_mode = r.choice("drive_mode", s->drive_mode, {"auto", "omnidirectional", "differential"});
  s->obstacle_range = r.number("obstacle_range", s->obstacle_range, R::above(0.0), "m");
  s->obstacle_check_ahead = r.number("obstacle_check_ahead", s->obstacle_check_ahead, R::above(0.0), "m");
  s->goal.obstacle_wait_s = r.number("obstacle_wait", s->goal.obstacle_wait_s, R::above(0.0), "s");
  s->goal.planner_patience_s = r.number("planner_patience", s->goal.planner_patience_s, R::above(0.0), "s");
  s->goal.settle_time_s = r.number("settle_time", s->goal.settle_time_s, R::closed(0.0, 5.0), "s");
  s->goal.goal_corrections = r.integer("goal_corrections", s->goal.goal_corrections, 0, 20);
  s->goal.replan_distance_m = r.number("replan_distance", s->goal.replan_distance_m, R::aboveUpTo(0.0, 100.0), "m");
  s->final_approach = r.number("final_approach", s->final_approach, R::closed(0.0, 2.0), "m");
  s->obstacle_update_rate = r.number("obstacle_update_rate", s->obstacle_update_rate, R::aboveUpTo(0.0, 100.0), "Hz");
  s->scan_max_age = r.number("scan_max_age", s->scan_max_age, R::above(0.0), "s");
  s->costmap.inflation_radius_m = r.number("inflation_radius", s->costmap.inflation_radius_m, R::atLeast(0.0), "m");
  // 0: half the footprint's width (+ padding), set below.
  s->costmap.planning_radius_m = r.number("planning_radius", 0.0, R::atLeast(0.0), "m");
  s->costmap.cost_scaling = r.number("cost_scaling_factor", s->costmap.cost_scaling, R::above(0.0), "1/m");
  s->costmap.unknown_is_blocked = !r.flag("allow_unknown", !s->costmap.unknown_is_blocked);
  s->costmap.known_structure_tolerance_m =
      r.number("known_structure_tolerance", s->costmap.known_structure_tolerance_m, R::closed(0.0, 1.0), "m");
  s->planner.cost_weight = r.number("cost_weight", s->planner.cost_weight, R::atLeast(0.0));
}

/// The path follower's keys, in the order they are read: name, member, range, unit.
struct FollowerKey {
  const char* name;
  double FollowerParams::*member;
  R range;
  const char* unit;
};

void readFollowerParams(thorvald_common::ParamReader& r, FollowerParams* f) {
  const FollowerKey keys[] = {
      {"max_vel_x", &FollowerParams::max_speed_mps, R::above(0.0), "m/s"},
      {"max_vel_theta", &FollowerParams::max_yaw_rate_radps, R::above(0.0), "rad/s"},
      {"acc_lim_x", &FollowerParams::max_accel_mps2, R::above(0.0), "m/s^2"},
      {"acc_lim_theta", &FollowerParams::max_yaw_accel_radps2, R::above(0.0), "rad/s^2"},
      {"xy_goal_tolerance", &FollowerParams::xy_tolerance_m, R::above(0.0), "m"},
      {"yaw_goal_tolerance", &FollowerParams::yaw_tolerance_rad, R::above(0.0), "rad"},
      {"lookahead", &FollowerParams::lookahead_m, R::above(0.0), "m"},
      {"rotate_in_place_angle", &FollowerParams::rotate_in_place_rad, R::closed(0.0, 3.1416), "rad"},
      {"arrive_fraction", &FollowerParams::arrive_fraction, R::closed(0.05, 1.0), ""},
      {"command_latency", &FollowerParams::command_latency_s, R::closed(0.0, 2.0), "s"},
      {"min_vel_theta", &FollowerParams::min_yaw_rate_radps, R::above(0.0), "rad/s"},
  };
  for (const auto& k : keys) f->*k.member = r.number(k.name, f->*k.member, k.range, k.unit);
  f->max_turn_reversals = r.integer("max_turn_reversals", f->max_turn_reversals, 0, 20);
}

/// The outline of the robot's collision shapes in the namespace's `robot_description` (the URDF thorvald_model writes
/// from the robot file and its frame extras: the frame, not only the wheels); false when there is none.
bool footprintFromDescription(const ros::NodeHandle& nh, Settings* s) {
  std::string urdf;
  if (!nh.getParam("robot_description", urdf) || urdf.empty()) return false;
  const UrdfFootprint u = footprintFromUrdf(urdf, s->base_frame);
  check(u.error.empty() ? "" : "robot_description in " + nh.getNamespace() + ": " + u.error);
  for (const auto& link : u.skipped)
    ROS_WARN("headland_navigator: link %s has a mesh collision shape, left out of the footprint", link.c_str());
  s->footprint.clear();
  for (const auto& p : u.footprint.polygon) s->footprint.insert(s->footprint.end(), {p.x(), p.y()});
  ROS_INFO("headland_navigator: footprint from robot_description: %d collision shapes, %zu corners", u.shapes,
           u.footprint.polygon.size());
  return true;
}

/// The footprint from the robot's description (footprintFromDescription), else the box around the wheels, casters and
/// corners of the robot file in the robot's namespace; an "auto" drive mode becomes omnidirectional when every drive
/// steers and no passive wheel drags.
void footprintFromRobotFile(const ros::NodeHandle& nh, Settings* s) {
  thorvald_base::RobotConfig cfg;
  try {
    cfg = thorvald_base::robotConfigFromParams(nh);
  } catch (const std::exception& e) {
    check("no ~footprint and no usable robot file in " + nh.getNamespace() + ": " + e.what());
  }
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  auto grow = [&](double x, double y, double rx, double ry) {
    x0 = std::min(x0, x - rx);
    x1 = std::max(x1, x + rx);
    y0 = std::min(y0, y - ry);
    y1 = std::max(y1, y + ry);
  };
  bool all_steered = !cfg.drives.empty();
  for (const auto& d : cfg.drives) {
    grow(d.x, d.y, d.r_wheel, 0.5 * d.w_wheel);
    all_steered = all_steered && d.type == 0;
  }
  for (const auto& c : cfg.casters) grow(c.x, c.y, c.r_wheel + c.offset, 0.5 * c.w_wheel);
  for (const auto& c : cfg.passive_wheels) grow(c.x, c.y, c.r_wheel, 0.5 * c.w_wheel);
  for (const auto& c : cfg.corners) grow(c.x, c.y, 0.05, 0.05);
  if (!footprintFromDescription(nh, s)) s->footprint = {x0, y0, x1, y0, x1, y1, x0, y1};
  if (s->drive_mode == "auto")
    s->drive_mode = all_steered && cfg.passive_wheels.empty() ? "omnidirectional" : "differential";
}

}  // namespace

bool loadSettings(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, Settings* s, std::string* error) {
  try {
    thorvald_common::ParamReader r(pnh, "headland_navigator");
    readNavigatorParams(r, s);
    auto& f = s->goal.follower;
    readFollowerParams(r, &f);
    r.finish();
    if (!s->footprint.empty() && (s->footprint.size() < 6 || s->footprint.size() % 2 != 0))
      check("~footprint must be a flat list x0 y0 x1 y1 ... of at least 3 points, got " +
            std::to_string(s->footprint.size()) + " numbers");
    if (s->footprint.empty()) footprintFromRobotFile(nh, s);
    if (s->drive_mode == "auto") s->drive_mode = "differential";
    f.omnidirectional = s->drive_mode == "omnidirectional";
    if (s->costmap.planning_radius_m <= 0.0)
      s->costmap.planning_radius_m = makeFootprint(s->footprint, s->footprint_padding).halfWidth();
    s->costmap.inflation_radius_m = std::max(s->costmap.inflation_radius_m, s->costmap.planning_radius_m);
    check(s->costmap.validate());
    check(s->planner.validate());
    check(s->goal.validate());
  } catch (const thorvald_common::ParamError& e) {
    *error = e.what();
    return false;
  }
  return true;
}

}  // namespace thorvald_navigation
