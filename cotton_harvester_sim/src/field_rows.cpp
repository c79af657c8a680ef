#include "cotton_harvester_sim/field_rows.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester_sim/field_pose.h"

namespace cotton_harvester {
namespace sim {

namespace {

using control::Pose2;

/// One stretch the rover follows: a row (harvest speed) or a headland turn.
struct Leg {
  bool turn = false;
  int row = 0;  ///< the row driven, or the row the turn leaves
  control::WaypointPath path;
  double planned_depth_m = 0.0;  ///< a turn's depth past the row's last plant, as planned [m]
};

/// The true front axle (scoring only): the articulation joint and the front half's heading, read through the camera
/// that the front half carries.
Pose2 truthFrontAxle(const RoverSim& sim, double axle_to_joint_m) {
  const Eigen::Vector3d c0 = sim.toCamera(Eigen::Vector3d::Zero());
  const Eigen::Vector3d cx = sim.toCamera(Eigen::Vector3d::UnitX()), cy = sim.toCamera(Eigen::Vector3d::UnitY());
  const double yaw = std::atan2((cy - c0).y(), (cx - c0).y());  // the optical y axis is the body's forward
  const Eigen::Vector3d j = sim.roverPosition();
  return {j.x() + axle_to_joint_m * std::cos(yaw), j.y() + axle_to_joint_m * std::sin(yaw), yaw};
}

/// The legs: row 0 from the start, then per row an omega turn on the headland and the next row back.
std::vector<Leg> planLegs(const FieldRowsConfig& c, const thorvald_sim::CottonFieldTruth& f,
                          const Eigen::Vector2d& start) {
  std::vector<Leg> legs;
  Eigen::Vector2d from = start;
  const int rows = static_cast<int>(f.row_start.size());
  for (int k = 0; k < rows; ++k) {
    const double dir = k % 2 == 0 ? 1.0 : -1.0;
    const Eigen::Vector2d last = dir > 0 ? f.row_end[k] : f.row_start[k];
    const Eigen::Vector2d to = last + Eigen::Vector2d(dir * c.past_row_end_m, 0.0);
    legs.push_back({false, k, control::WaypointPath({from, to}), 0.0});
    if (k + 1 == rows) break;
    const double lateral = dir * (f.row_start[k + 1].y() - f.row_start[k].y());
    const control::RowTurn turn = control::planRowTurn(to, dir > 0 ? 0.0 : M_PI, lateral, c.turn);
    // The plan's depth counts from where the turn starts, past_row_end_m beyond the row's last plant; the scorer
    // measures from the last plant: the leg carries the plan's depth from there too.
    legs.push_back({true, k, control::WaypointPath(turn.waypoints), c.past_row_end_m + turn.depth_m});
    from = turn.waypoints.back();
  }
  return legs;
}

/// Scores the truth against the legs while the rover drives them.
class FieldScorer {
 public:
  FieldScorer(const FieldRowsConfig& c, const thorvald_sim::CottonFieldTruth& f, FieldRowsReport* r)
      : c_(c), f_(f), r_(r) {}

  void startLeg(const Leg& leg, double now_s) {
    leg_ = leg;
    leg_start_s_ = now_s;
    sum_sq_ = 0.0;
    samples_ = 0;
    max_abs_ = 0.0;
    passed_last_ = false;
    depth_ = 0.0;
    entry_scored_ = false;
  }

  void observe(const Pose2& truth) {
    const int k = leg_.row;
    const double dir = k % 2 == 0 ? 1.0 : -1.0;
    if (!leg_.turn) {
      const double x0 = std::min(f_.row_start[k].x(), f_.row_end[k].x());
      const double x1 = std::max(f_.row_start[k].x(), f_.row_end[k].x());
      if (truth.x >= x0 && truth.x <= x1) {
        const double e = truth.y - f_.row_start[k].y();
        sum_sq_ += e * e;
        ++samples_;
        max_abs_ = std::max(max_abs_, std::abs(e));
      }
      passed_last_ = passed_last_ || dir * (truth.x - (dir > 0 ? x1 : x0)) > 0.0;
      // The turn before this row is scored where the rover enters it: at the row's first plant.
      if (k > 0 && !entry_scored_ && !r_->turns.empty() && dir * (truth.x - (dir > 0 ? x0 : x1)) >= 0.0) {
        entry_scored_ = true;
        FieldTurnReport& turn = r_->turns.back();
        turn.entry_cross_track_m = truth.y - f_.row_start[k].y();
        turn.entry_heading_deg = control::wrapAngle(truth.yaw - (dir > 0 ? 0.0 : M_PI)) * 180.0 / M_PI;
        turn.success = turn.success && std::abs(turn.entry_cross_track_m) <= c_.entry_tolerance_m &&
                       std::abs(turn.entry_heading_deg) <= c_.entry_tolerance_deg;
      }
      return;
    }
    const double end_x = dir > 0 ? f_.row_end[k].x() : f_.row_start[k].x();
    depth_ = std::max(depth_, dir * (truth.x - end_x));
  }

  void endLeg(double now_s, const Pose2& truth, const Pose2& estimate, bool finished) {
    if (!leg_.turn) {
      FieldRowReport row;
      row.row = leg_.row;
      row.cross_track_rms_m = samples_ ? std::sqrt(sum_sq_ / samples_) : 0.0;
      row.cross_track_max_m = max_abs_;
      row.completed = finished && passed_last_ && max_abs_ < 0.25;
      row.odometry_error_m = std::hypot(estimate.x - truth.x, estimate.y - truth.y);
      row.time_s = now_s - leg_start_s_;
      r_->rows.push_back(row);
      all_sum_sq_ += sum_sq_;
      all_samples_ += samples_;
      return;
    }
    FieldTurnReport turn;
    turn.from_row = leg_.row;
    turn.entry_cross_track_m = NAN;  // until the rover enters the next row
    turn.entry_heading_deg = NAN;
    turn.depth_m = depth_;
    turn.planned_depth_m = leg_.planned_depth_m;
    // Within the headland the plan asked for (0.5 m of slack); the entry decides the rest.
    turn.success = finished && depth_ <= leg_.planned_depth_m + 0.5;
    r_->turns.push_back(turn);
  }

  double allRms() const { return all_samples_ ? std::sqrt(all_sum_sq_ / all_samples_) : 0.0; }

 private:
  const FieldRowsConfig& c_;
  const thorvald_sim::CottonFieldTruth& f_;
  FieldRowsReport* r_;
  Leg leg_;
  double leg_start_s_ = 0.0, sum_sq_ = 0.0, max_abs_ = 0.0, depth_ = 0.0, all_sum_sq_ = 0.0;
  long samples_ = 0, all_samples_ = 0;
  bool passed_last_ = false, entry_scored_ = false;
};

Pose2 compose(const Pose2& start, const control::ArticulatedOdometry& odom) {
  const double c = std::cos(start.yaw), s = std::sin(start.yaw);
  return {start.x + c * odom.x() - s * odom.y(), start.y + s * odom.x() + c * odom.y(),
          control::wrapAngle(start.yaw + odom.yaw())};
}

std::string legLine(const Leg& leg, int legs_done, int legs, double now_s, const char* what) {
  char line[160];
  std::snprintf(line, sizeof(line), "field_rows: t %.1f s, leg %d/%d: %s %s %d", now_s, legs_done + 1, legs, what,
                leg.turn ? "turn after row" : "row", leg.row);
  return line;
}

/// The share of the speed while the articulation lags its set-point by `lag_deg` (FieldRowsConfig::lag_slow_*).
double lagSpeedFraction(const FieldRowsConfig& c, double lag_deg) {
  if (!(c.lag_slow_from_deg > 0.0) || !std::isfinite(lag_deg)) return 1.0;
  const double span = std::max(1e-6, c.lag_slow_full_deg - c.lag_slow_from_deg);
  const double share = std::clamp((std::abs(lag_deg) - c.lag_slow_from_deg) / span, 0.0, 1.0);
  return 1.0 - share * (1.0 - c.lag_min_speed_fraction);
}

/// The pose the rover drives on: the fused estimate (FieldPose) or its wheel odometry from the surveyed start.
class DrivePose {
 public:
  DrivePose(const FieldRowsConfig& c, const RoverSim& sim, const Pose2& start)
      : start_(start), odometry_(c.rover.axle_to_joint_m) {
    if (c.fused_pose) fused_ = std::make_unique<FieldPose>(sim, c.sim.seed, c.fusion, c.sensor_realism);
  }
  void afterStep() {
    if (fused_) fused_->afterStep();
  }
  void odometry(double travel_m, double articulation_deg, double dt) {
    odometry_.update(travel_m, articulation_deg, dt);
  }
  Pose2 estimate(double t) { return fused_ ? fused_->estimate(t) : compose(start_, odometry_); }
  double speed() const { return odometry_.speed(); }
  /// The fusion's health (always ok on the wheel odometry alone); not ok until the GNSS datum is set.
  thorvald_navigation::FusionHealth health(double t) const {
    if (!fused_) return {};
    if (!fused_->ready()) {
      thorvald_navigation::FusionHealth h;
      h.level = thorvald_navigation::FusionHealth::kError;
      h.localization_ok = false;
      h.reasons.push_back("waiting for the GNSS datum (the first fixed epoch)");
      return h;
    }
    return fused_->health(t);
  }

 private:
  Pose2 start_;
  control::ArticulatedOdometry odometry_;
  std::unique_ptr<FieldPose> fused_;
};

/// Advances the bridge by one control period in physics steps, the sensors polled after each.
RoverSerialBridge::Output advanceControlPeriod(const FieldRowsConfig& c, const RoverSim& sim, RoverSerialBridge& bridge,
                                               DrivePose& pose) {
  RoverSerialBridge::Output out;
  const double dt = sim.params().timestep_s;
  const long steps = std::max(1L, std::lround(c.control_period_s / dt));
  for (long i = 0; i < steps; ++i) {
    RoverSerialBridge::Output o = bridge.advance(dt);
    out.navigation.insert(out.navigation.end(), o.navigation.begin(), o.navigation.end());
    pose.afterStep();
  }
  return out;
}

/// The drive itself: the rover's controller on the bridge's telemetry, pure pursuit on the pose, the gate.
void driveLegs(const FieldRowsConfig& c, RoverSim& sim, const std::vector<Leg>& legs, FieldRowsReport* report) {
  RoverSerialBridge bridge(sim, c.bridge);
  control::RoverController controller(c.rover);
  control::NavigationFrameParser telemetry_parser;
  control::PurePursuit pursuit(c.pursuit);
  const double a = c.rover.axle_to_joint_m;
  DrivePose pose(c, sim, truthFrontAxle(sim, a));  // the surveyed start: where the user puts the rover
  DriveGate gate(c.resume_after_s);
  FieldScorer scorer(c, report->field, report);
  const int n = static_cast<int>(legs.size());
  size_t leg = 0;
  pursuit.setPath(legs[0].path);
  scorer.startLeg(legs[0], sim.time());
  if (c.progress) c.progress(legLine(legs[0], 0, n, sim.time(), "start"));
  bool has_telemetry = false;
  std::uint8_t sequence = 0;
  double next_sample_s = 0.0, t0 = sim.time();
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> trace(nullptr, &std::fclose);
  if (!c.trace_path.empty()) {
    trace.reset(std::fopen(c.trace_path.c_str(), "w"));
    if (!trace) throw std::runtime_error("cannot write " + c.trace_path);
    std::fprintf(trace.get(),
                 "t,leg,turn,row,truth_x,truth_y,truth_yaw,est_x,est_y,est_yaw,art_target_deg,art_measured_deg,"
                 "art_true_deg,curvature_1pm,cross_track_m,s_m,remaining_m,speed_mps,heading_correction_deg\n");
  }
  while (leg < legs.size() && sim.time() - t0 < c.time_limit_s) {
    const RoverSerialBridge::Output out = advanceControlPeriod(c, sim, bridge, pose);
    telemetry_parser.push(out.navigation.data(), out.navigation.size());
    for (const control::Telemetry& t : telemetry_parser.takeTelemetry()) {
      const Pose2 estimate = pose.estimate(sim.time());
      const Pose2 truth = truthFrontAxle(sim, a);
      scorer.observe(truth);
      if (sim.time() >= next_sample_s) {
        next_sample_s = sim.time() + 0.2;
        report->truth_path.emplace_back(truth.x, truth.y);
        report->estimate_path.emplace_back(estimate.x, estimate.y);
      }
      if (const auto change = gate.update(pose.health(sim.time()), sim.time()); change && c.progress) {
        char line[64];
        std::snprintf(line, sizeof line, "field_rows: t %.1f s, ", sim.time());
        c.progress(line + *change);
      }
      double speed = 0.0, articulation = controller.articulationDeg();
      if (!gate.stopped()) {
        const control::PursuitStep step = pursuit.update(estimate, pose.speed());
        if (step.finished) {
          scorer.endLeg(sim.time(), truth, estimate, true);
          if (c.progress) c.progress(legLine(legs[leg], static_cast<int>(leg), n, sim.time(), "done"));
          if (++leg == legs.size()) break;
          pursuit.setPath(legs[leg].path);
          scorer.startLeg(legs[leg], sim.time());
          if (c.progress) c.progress(legLine(legs[leg], static_cast<int>(leg), n, sim.time(), "start"));
        }
        speed = (legs[leg].turn ? c.turn_speed_mps : c.row_speed_mps) *
                lagSpeedFraction(c, step.articulation_deg - controller.articulationDeg());
        articulation = step.articulation_deg;
        if (trace)
          std::fprintf(trace.get(),
                       "%.3f,%zu,%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.2f,%.2f,%.2f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f\n",
                       sim.time(), leg, legs[leg].turn ? 1 : 0, legs[leg].row, truth.x, truth.y, truth.yaw, estimate.x,
                       estimate.y, estimate.yaw, step.articulation_deg, controller.articulationDeg(),
                       sim.potentiometerDeg(), step.curvature_1pm, step.cross_track_m, step.s_m, step.remaining_m,
                       pose.speed(), step.heading_correction_rad * 180.0 / M_PI);
      }
      controller.setVelocity(speed, 0.0);
      controller.setArticulationTarget(articulation);
      const double before = controller.positionM();
      control::DriveCommand command = controller.update(t, c.control_period_s).command();
      if (has_telemetry)
        pose.odometry(controller.positionM() - before, controller.articulationDeg(), c.control_period_s);
      has_telemetry = true;
      command.sequence = sequence++;
      const auto frame = control::encodeDriveCommand(command);
      bridge.receiveNavigation(frame.data(), frame.size());
    }
  }
  if (leg < legs.size()) {
    scorer.endLeg(sim.time(), truthFrontAxle(sim, a), pose.estimate(sim.time()), false);
    report->error = "time limit: " + std::to_string(c.time_limit_s) + " s";
  }
  report->cross_track_rms_m = scorer.allRms();
  report->stops = gate.stops();
  report->stopped_s = gate.stoppedTotalS();
}

}  // namespace

FieldRowsReport runFieldRows(const FieldRowsConfig& config) {
  FieldRowsReport report;
  const auto wall0 = std::chrono::steady_clock::now();
  try {
    if (const std::string bad = config.rover.check(); !bad.empty()) throw std::invalid_argument("rover: " + bad);
    if (!(config.lag_slow_from_deg >= 0.0) || !(config.lag_slow_full_deg > config.lag_slow_from_deg) ||
        !(config.lag_min_speed_fraction > 0.0 && config.lag_min_speed_fraction <= 1.0))
      throw std::invalid_argument(
          "lag_slow_from_deg >= 0, lag_slow_full_deg > lag_slow_from_deg and lag_min_speed_fraction in (0, 1] "
          "expected");
    RoverSimParams params = config.sim;
    params.field = config.field;
    thorvald_sim::makeCottonFieldWorld(config.field, &report.field);
    const double first_x = report.field.row_start[0].x();
    params.start_x_m = first_x - config.start_before_row_m - config.rover.axle_to_joint_m;
    RoverSim sim(params);
    if (!config.waypoints_path.empty() && !thorvald_sim::writeCottonFieldWaypoints(report.field, config.waypoints_path))
      throw std::runtime_error("cannot write " + config.waypoints_path);
    const Pose2 start = truthFrontAxle(sim, config.rover.axle_to_joint_m);
    const std::vector<Leg> legs = planLegs(config, report.field, {start.x, start.y});
    for (const Leg& leg : legs)
      report.planned_path.insert(report.planned_path.end(), leg.path.waypoints().begin(), leg.path.waypoints().end());
    const double t0 = sim.time();
    driveLegs(config, sim, legs, &report);
    report.sim_time_s = sim.time() - t0;
    report.bolls = sim.bolls();
  } catch (const std::exception& e) {
    report.error = e.what();
  }
  int completed = 0, turned = 0;
  for (const auto& r : report.rows) completed += r.completed ? 1 : 0;
  for (const auto& t : report.turns) turned += t.success ? 1 : 0;
  const int rows = config.field.rows;
  report.rows_completed_pct = rows > 0 ? 100.0 * completed / rows : 0.0;
  report.turn_success_pct = rows > 1 ? 100.0 * turned / (rows - 1) : 100.0;
  report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return report;
}

FieldRowsConfig fieldRowsConfig(int rows, double length_m, unsigned seed) {
  FieldRowsConfig c;
  c.field.rows = rows;
  c.field.row_length_m = length_m;
  c.field.row.first_plant_x_m = 3.0;
  c.field.row.seed = seed;
  c.field.row.leaves_per_plant = 2;
  c.sim.seed = seed;
  c.sim.differential_wheels = true;  // the wheels do not scrub in the turns
  c.sim.leaf_push_max_m = 0.0;       // the arm does not move while the rover only drives
  c.turn.straight_m = 1.5;           // straight and aligned before the next row's first plant
  c.turn.turn_radius_m = 2.5;        // the rover's smallest is 2.20 m (45 deg): 5 deg left for the relays' lag
  // The fused heading drifts by up to 3 deg in a turn (the IMUs' biases) and the filter takes it back slowly along
  // the rows: pure pursuit corrects it from the cross-track on the straights (else lookahead * tan(3 deg) beside).
  c.pursuit.heading_correction_gain = 0.2;
  c.lag_slow_from_deg = 2.0;  // the relays move the joint at 8 deg/s: slow while it lags more than 2 deg
  return c;
}

bool writeFieldPng(const FieldRowsReport& r, const std::string& path) {
  if (r.field.row_start.empty()) return false;
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& p : r.planned_path) {
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
  for (const auto& p : r.truth_path) {
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
  x0 -= 1.0, x1 += 1.0, y0 -= 1.0, y1 += 1.0;
  const double scale = std::min(60.0, 2400.0 / (x1 - x0));
  const int w = static_cast<int>((x1 - x0) * scale), h = static_cast<int>((y1 - y0) * scale) + 30;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(60, 80, 110));
  auto px = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>((p.x() - x0) * scale), static_cast<int>((y1 - p.y()) * scale) + 30);
  };
  for (const auto& b : r.field.plants.plant_bases) cv::circle(img, px(b.head<2>()), 2, cv::Scalar(40, 140, 40), -1);
  for (const auto& b : r.bolls)
    cv::circle(img, px(b.centre.head<2>()), 2, b.captured ? cv::Scalar(0, 200, 0) : cv::Scalar(0, 0, 230), -1);
  auto polyline = [&](const std::vector<Eigen::Vector2d>& pts, const cv::Scalar& colour, int width) {
    for (size_t i = 1; i < pts.size(); ++i) cv::line(img, px(pts[i - 1]), px(pts[i]), colour, width);
  };
  polyline(r.planned_path, cv::Scalar(200, 200, 200), 1);
  polyline(r.estimate_path, cv::Scalar(0, 140, 255), 1);
  polyline(r.truth_path, cv::Scalar(255, 160, 0), 2);
  cv::putText(
      img,
      "planned (grey), driven truth (blue), rover's odometry (orange), plants (green), bolls: picked green, missed red",
      cv::Point(5, 20), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1);
  return cv::imwrite(path, img);
}

}  // namespace sim
}  // namespace cotton_harvester
