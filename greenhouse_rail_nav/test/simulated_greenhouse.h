// The simulated greenhouse robot the UV mission's tests run against (no ROS): a differential robot with a lagged
// response in a headland with rail sets, a rail detector that sees the rail start from 0.65 to 3 m, the down-facing
// range finders over floor, pipes and the rows' lower ground, a far wall for the lidar, and a navigation that stops
// near the goal with an error. Included by the test sources of one test binary (test_uv_mission).
#pragma once

#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "greenhouse_rail_nav/uv_dose.h"
#include "greenhouse_rail_nav/uv_mission.h"

namespace grn = greenhouse_rail_nav;

namespace {

struct RailSetTruth {
  double y = 0.0;  ///< centre line of the set (the rails run along +x from x = 0, the headland edge)
};

class SimulatedGreenhouse : public grn::MissionIO {
 public:
  explicit SimulatedGreenhouse(std::vector<RailSetTruth> sets, unsigned seed = 1) : sets_(std::move(sets)), rng_(seed) {
    pose_ = odom_ = thorvald_base::Pose2D(-3.0, 0.0, 0.0);
  }

  // World settings the tests change.
  double rail_length = 12.0;
  double wall_past_end = 1.0;  ///< the far wall this far past the rails' end [m]
  double gauge = 0.55;
  double nav_xy_error = 0.08, nav_yaw_error = 0.06;
  double detector_y_bias = 0.0;
  double bumper_from = -1.0, bumper_to = -1.0;  ///< sim time of a bumper press and of the person's reset
  /// Odometry gain while reversing on the rails (> 1: odometry runs ahead of the robot, as when the wheels slip).
  double odom_reverse_gain_on_rails = 1.0;
  double silent_after_lights_s = -1.0;        ///< the range finders stop reporting after the lights were on this long
  double odom_period_s = 0.0;                 ///< odometry comes at this period (0: every control tick)
  int failing_nav_goals = 0;                  ///< this many navigation goals (the first ones) end in failure
  grn::UvMission* preempt_mission = nullptr;  ///< preempted once the robot has driven preempt_on_rails_x onto the rails
  double preempt_on_rails_x = -1.0;
  double person_x = 0.0, person_from = -1.0, person_to = -1.0;  ///< a person standing in set 0's row, from .. to [s]
  /// The lamps' relay confirms "on" this long after the request, "off" at once (< 0: no confirmed state reported).
  double relay_on_delay_s = -1.0;
  /// > 0: the lamps light only while the robot moves at least this fast, as uv_interlock switches them [m/s].
  double interlock_min_speed_mps = 0.0;
  /// From when the robot, backing off set 0's rails, first has its wheels on the floor: it stands pinned (against
  /// something it backed into), its wheels turning. Odometry then integrates the commanded speed along its own heading,
  /// which is off the robot's by this much [rad], and turns only as the robot does (the gyro's yaw). NaN: never.
  double pinned_odom_yaw_error = std::numeric_limits<double>::quiet_NaN();
  double pinned_driving_s = 0.0;  ///< time the wheels turned (a speed commanded) while pinned [s]
  double response_s = 0.12;       ///< the drives' time constant: how fast the robot follows a twist (and brakes) [s]
  /// Something standing on the headland at this x behind set 0's target pose (a parked trolley), seen by the rear
  /// range finders 0.87 m behind base_link while the robot faces along +x within 0.5 m of set 0's line; NaN: nothing.
  double obstacle_behind_x = std::numeric_limits<double>::quiet_NaN();
  /// [m] closest the rear range finders came to it with base_link in front of it
  double min_gap_behind = std::numeric_limits<double>::infinity();
  int lit_ticks_with_person = 0;  ///< control ticks with the lights on and the person ahead in the row
  double closest_to_person = std::numeric_limits<double>::infinity();  ///< [m] base_link to the person

  // What the tests check.
  bool wheel_past_edge = false;
  bool lights_on = false;
  bool lights_on_off_rails = false;
  double lights_on_time = 0.0;
  double first_lights_on_x = std::numeric_limits<double>::quiet_NaN();  ///< base_link's x when the lights first went on
  double last_lights_off_x = std::numeric_limits<double>::quiet_NaN();  ///< base_link's x when the lights last went off
  double max_x = -1e9;                                                  ///< farthest base_link went [m]
  int nav_goals = 0;
  bool nav_goal_on_rails = false;  ///< a navigation goal was sent while the wheels read rail
  int localisation_resets = 0;
  std::vector<std::string> lines;
  /// The UV dose along set 0's row (rails from x = 0 to rail_length) from the lamps as they lit (uv_dose's model).
  std::unique_ptr<grn::RowDose> set0_dose;

  double now() override { return t_; }
  bool ok() override { return t_ < 3600.0; }
  void waitTick() override { step(0.02); }
  void sendNavGoal(const thorvald_base::Pose2D& goal) override {
    ++nav_goals;
    if (surface_.wheels == grn::Surface::kRail) nav_goal_on_rails = true;
    goal_ = goal;
    nav_done_at_ = t_ + 5.0;
  }
  grn::NavState navState(std::string*) override {
    if (nav_done_at_ < 0.0) return grn::NavState::kIdle;
    if (t_ < nav_done_at_) return grn::NavState::kActive;
    if (nav_done_at_ > 0.0 && nav_goals <= failing_nav_goals) {
      nav_done_at_ = 0.0;
      return grn::NavState::kFailed;
    }
    if (nav_done_at_ > 0.0) {
      std::normal_distribution<double> exy(0.0, nav_xy_error), eyaw(0.0, nav_yaw_error);
      pose_ = thorvald_base::Pose2D(goal_.x + exy(rng_), goal_.y + exy(rng_), goal_.yaw + eyaw(rng_));
      odom_ = thorvald_base::Pose2D(pose_.x + odom_extra_x_, pose_.y, pose_.yaw);
      v_ = w_ = 0.0;
      pinned_ = false;
      nav_done_at_ = 0.0;
    }
    return grn::NavState::kSucceeded;
  }
  void cancelNav() override { nav_done_at_ = -1.0; }
  bool odomPose(thorvald_base::Pose2D* p) override {
    *p = odom_;
    return true;
  }
  bool mapPose(thorvald_base::Pose2D* p) override {
    *p = pose_;
    return true;
  }
  grn::RailObservation railObservation() override { return obs_; }
  grn::SurfaceReading surface() override { return surface_; }
  thorvald_base::Pose2D truePose() const { return pose_; }
  double lastLinearCommand() const { return v_cmd_; }
  double forwardRange() override {
    // The far wall 1 m past the rail end, seen by the lidar 0.45 m ahead of base_link when facing along +x.
    if (std::cos(pose_.yaw) < 0.9) return std::numeric_limits<double>::quiet_NaN();
    return (rail_length + wall_past_end - (pose_.x + 0.45 * std::cos(pose_.yaw))) / std::cos(pose_.yaw);
  }
  bool safetyStopped(std::string* why) override {
    const bool stopped = t_ >= bumper_from && t_ < bumper_to;
    if (stopped) *why = "bumper pressed";
    return stopped;
  }
  void commandTwist(double v, double w) override {
    EXPECT_TRUE(std::isfinite(v) && std::isfinite(w));
    if (t_ >= bumper_from && t_ < bumper_to) {
      EXPECT_EQ(v, 0.0) << "moving during a safety stop";
    }
    v_cmd_ = v;
    w_cmd_ = w;
  }
  void setLights(bool on) override {
    if (on && !lights_on && std::isnan(first_lights_on_x)) first_lights_on_x = pose_.x;
    if (!on && lights_on) last_lights_off_x = pose_.x;
    if (on && !lights_on) lights_request_t_ = t_;
    lights_on = on;
  }
  bool lampsConfirmed(bool* on) override {
    if (relay_on_delay_s < 0.0) return false;
    *on = lampsLit();
    return true;
  }
  void resetLocalisation(const thorvald_base::Pose2D&) override { ++localisation_resets; }
  void log(const std::string& line) override { lines.push_back(line); }
  void setZoneContext(const grn::ZoneContext& c) override { zone_ctx_ = c; }
  grn::ZoneVerdict zone() override {
    // The lidar sees the person between the rails of the set the robot is on, ahead of it.
    grn::ZoneVerdict v;
    if (zone_ctx_.phase == grn::ZonePhase::kReverse && std::isfinite(obstacle_behind_x))
      return grn::evaluateZone({}, 0.45, zone_ctx_, grn::ZoneParams(), {}, {gapBehind()});
    v.end_range_m = forwardRange();
    if (personAhead() && zone_ctx_.phase == grn::ZonePhase::kRow) {
      v.blocked = v.person = true;
      v.why = "a person in the row ahead";
      v.end_range_m = std::numeric_limits<double>::quiet_NaN();
    }
    return v;
  }
  double gapBehind() const {
    if (std::fabs(pose_.y - sets_[0].y) > 0.5) return std::numeric_limits<double>::infinity();
    return pose_.x - 0.87 - obstacle_behind_x;
  }
  bool personAhead() const {
    return t_ >= person_from && t_ < person_to && std::fabs(pose_.y - sets_[0].y) < 0.3 && person_x > pose_.x;
  }

  grn::Surface surfaceAt(double lx, double ly) const {
    const double c = std::cos(pose_.yaw), s = std::sin(pose_.yaw);
    const double x = pose_.x + c * lx - s * ly, y = pose_.y + s * lx + c * ly;
    if (x < 0.0) return grn::Surface::kFloor;
    for (const auto& set : sets_)
      for (double side : {-0.5, 0.5})
        if (std::fabs(y - (set.y + side * gauge)) < 0.05 && x < rail_length) return grn::Surface::kRail;
    return grn::Surface::kEdge;
  }

 private:
  bool lampsLit() const {
    if (!lights_on) return false;
    if (relay_on_delay_s >= 0.0 && t_ - lights_request_t_ < relay_on_delay_s - 1e-9) return false;
    return !(interlock_min_speed_mps > 0.0 && std::fabs(v_) < interlock_min_speed_mps);
  }
  void step(double dt) {
    if (std::isfinite(obstacle_behind_x) && pose_.x > obstacle_behind_x)  // the robot in front of it
      min_gap_behind = std::min(min_gap_behind, gapBehind());
    if (!set0_dose) set0_dose = std::make_unique<grn::RowDose>(grn::UvDoseParams(), rail_length);
    const double x_before = pose_.x;
    const bool lit = lampsLit();
    const double a = std::min(1.0, dt / response_s);
    v_ += a * (v_cmd_ - v_);
    w_ += a * (w_cmd_ - w_);
    if (surface_.wheels == grn::Surface::kRail) been_on_rails_ = true;
    if (!std::isnan(pinned_odom_yaw_error) && been_on_rails_ && surface_.wheels == grn::Surface::kFloor &&
        v_cmd_ < 0.0) {
      pinned_ = true;
      pinned_yaw_offset_ = pinned_odom_yaw_error;
      pinned_odom_yaw_error = std::numeric_limits<double>::quiet_NaN();  // once
    }
    if (pinned_) {
      if (v_cmd_ != 0.0) pinned_driving_s += dt;
      odom_.yaw = thorvald_base::normalizeAngle(pose_.yaw + pinned_yaw_offset_);
      odom_.x += v_ * std::cos(odom_.yaw) * dt;
      odom_.y += v_ * std::sin(odom_.yaw) * dt;
      t_ += dt;
      updateSensors();
      return;
    }
    pose_.yaw = thorvald_base::normalizeAngle(pose_.yaw + w_ * dt);
    pose_.x += v_ * std::cos(pose_.yaw) * dt;
    if (v_ < 0.0 && surface_.wheels == grn::Surface::kRail)
      odom_extra_x_ += (odom_reverse_gain_on_rails - 1.0) * v_ * std::cos(pose_.yaw) * dt;
    pose_.y += v_ * std::sin(pose_.yaw) * dt;
    // On the pipes the rail wheels guide the robot along the rails.
    if (pose_.x > 0.1 && surface_.wheels == grn::Surface::kRail) {
      for (const auto& set : sets_)
        if (std::fabs(pose_.y - set.y) < 0.05) pose_.y = set.y, pose_.yaw = 0.0;
    }
    if (std::fabs(pose_.y - sets_[0].y) < 0.05 && x_before >= 0.0 && pose_.x >= 0.0)
      set0_dose->add(x_before, pose_.x, dt, lit);
    t_ += dt;
    max_x = std::max(max_x, pose_.x);
    if (t_ - last_odom_ >= odom_period_s - 1e-9) {
      odom_ = pose_;
      odom_.x += odom_extra_x_;
      last_odom_ = t_;
    }
    if (preempt_mission && preempt_on_rails_x >= 0.0 && pose_.x > preempt_on_rails_x) {
      preempt_mission->requestPreempt();
      preempt_on_rails_x = -1.0;
    }
    updateSensors();
    if (lights_on) lights_on_time += dt;
    if (personAhead()) {
      lit_ticks_with_person += lights_on ? 1 : 0;
      closest_to_person = std::min(closest_to_person, person_x - pose_.x);
    }
  }
  void updateSensors() {
    // Drive wheels at base_link +-0.2 m: the range finders at +-0.30 m beside them watch the rail wheels' line.
    const grn::Surface wl = surfaceAt(0.0, 0.30), wr = surfaceAt(0.0, -0.30);
    const grn::Surface fl = surfaceAt(0.52, 0.30), fr = surfaceAt(0.52, -0.30);
    if (silent_after_lights_s >= 0.0 && lights_on_time > silent_after_lights_s) return;
    auto common = [](grn::Surface a, grn::Surface b) {
      if (a == grn::Surface::kEdge || b == grn::Surface::kEdge) return grn::Surface::kEdge;
      return a == b ? a : grn::Surface::kUnknown;
    };
    surface_ = {common(fl, fr), common(wl, wr), t_};
    if (surface_.wheels == grn::Surface::kEdge) wheel_past_edge = true;
    if (lights_on && surface_.wheels != grn::Surface::kRail) lights_on_off_rails = true;
    // The detector: 15 Hz, sees the nearest set's start 0.65..3 m ahead within +-0.5 rad.
    if (t_ - last_cloud_ < 1.0 / 15.0) return;
    last_cloud_ = t_;
    obs_ = grn::RailObservation();
    obs_.stamp_s = t_;
    obs_.status = grn::RailObservation::Status::kNotFound;
    for (const auto& set : sets_) {
      const thorvald_base::Pose2D in_rail(pose_.x, pose_.y - set.y, pose_.yaw);
      const double bearing = std::atan2(-in_rail.y, -in_rail.x) - in_rail.yaw;
      if (in_rail.x > -3.0 && in_rail.x < 0.0 && std::fabs(thorvald_base::normalizeAngle(bearing)) < 0.5 &&
          std::fabs(in_rail.y) < 0.6) {
        std::normal_distribution<double> n(0.0, 0.004);
        obs_.robot_in_rail = thorvald_base::Pose2D(in_rail.x + 5 * n(rng_), in_rail.y + detector_y_bias + n(rng_),
                                                   in_rail.yaw + n(rng_));
        obs_.status =
            in_rail.x > -0.65 ? grn::RailObservation::Status::kXUnobserved : grn::RailObservation::Status::kFound;
      }
    }
  }

  std::vector<RailSetTruth> sets_;
  std::mt19937 rng_;
  thorvald_base::Pose2D pose_, goal_;
  double odom_extra_x_ = 0.0;
  bool been_on_rails_ = false, pinned_ = false;
  double pinned_yaw_offset_ = 0.0;
  thorvald_base::Pose2D odom_;     ///< the last odometry message's pose
  double last_odom_ = -1.0;        ///< when it came
  double lights_request_t_ = 0.0;  ///< when the lights were last asked on
  double t_ = 0.0, v_ = 0.0, w_ = 0.0, v_cmd_ = 0.0, w_cmd_ = 0.0, nav_done_at_ = -1.0, last_cloud_ = -1.0;
  grn::RailObservation obs_;
  grn::SurfaceReading surface_;
  grn::ZoneContext zone_ctx_;
};

std::vector<grn::MissionTarget> targetsFor(const std::vector<RailSetTruth>& sets, double approach_x) {
  std::vector<grn::MissionTarget> t;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    grn::MissionTarget m;
    m.index = static_cast<int>(i);
    m.target_pose = thorvald_base::Pose2D(approach_x, sets[i].y, 0.0);
    t.push_back(m);
  }
  return t;
}

}  // namespace

namespace {
bool logSays(const SimulatedGreenhouse& world, const std::string& text) {
  for (const auto& l : world.lines)
    if (l.find(text) != std::string::npos) return true;
  return false;
}
}  // namespace
