#include "cotton_harvester_sim/field_loop.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace cotton_harvester {
namespace sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

RoverSimParams loopSimParams(const FieldLoopConfig& c) {
  RoverSimParams p;
  p.realism = c.realism;
  p.seed = c.seed;
  p.row.slope_deg = c.slope_deg;
  p.row.seed = c.seed;
  p.row.plants = 1;  // one plant far beyond the loop: the ground is the field's, nothing in the rover's way
  p.row.bolls_per_plant = 0;
  p.row.first_plant_x_m = 150.0;
  p.camera_width = 64;  // the camera is never rendered here
  p.camera_height = 48;
  return p;
}

/// The scripted operator: legs and turns ended on the true travel and heading (the bench's driver, not the rover's).
class LoopDriver {
 public:
  LoopDriver(const FieldLoopConfig& c, const RoverPose2d& start) : c_(c), start_(start), last_(start) {}

  /// Commands for the pose now; false once the loop is closed.
  bool command(const RoverPose2d& now, double* pwm, double* articulation_deg) {
    travelled_ += std::hypot(now.x - last_.x, now.y - last_.y);
    turned_ += wrap(now.yaw - last_.yaw);
    last_ = now;
    *pwm = c_.pwm;
    *articulation_deg = 0.0;
    switch (phase_) {
      case 0:
      case 2:  // the long legs
        if (travelled_ - phase_start_ >= c_.straight_m) next();
        return true;
      case 1:
      case 3:  // U-turns to the left
        *articulation_deg = c_.turn_deg;
        if (turned_ - turn_start_ >= kPi) next();
        return true;
      default: {  // steering for the start until the rover crosses the start line
        const double along = std::cos(start_.yaw) * (now.x - start_.x) + std::sin(start_.yaw) * (now.y - start_.y);
        if (along >= 0.0) {
          *pwm = 90.0;
          return false;
        }
        const double bearing = std::atan2(start_.y - now.y, start_.x - now.x);
        *articulation_deg = std::clamp(2.0 * wrap(bearing - now.yaw) * 180.0 / kPi, -c_.turn_deg, c_.turn_deg);
        return true;
      }
    }
  }
  double travelled() const { return travelled_; }

 private:
  void next() {
    ++phase_;
    phase_start_ = travelled_;
    turn_start_ = turned_;
  }

  const FieldLoopConfig& c_;
  RoverPose2d start_, last_;
  int phase_ = 0;
  double travelled_ = 0.0, turned_ = 0.0, phase_start_ = 0.0, turn_start_ = 0.0;
};

/// The estimate's error against truth, both relative to base_link's pose at the start [m].
Eigen::Vector2d errorOf(const RoverPose2d& est, const RoverPose2d& truth, const RoverPose2d& start) {
  const Eigen::Vector2d d(truth.x - start.x, truth.y - start.y);
  const Eigen::Vector2d rel = Eigen::Rotation2Dd(-start.yaw) * d;
  return {est.x - rel.x(), est.y - rel.y()};
}

/// Outage bookkeeping for one filter.
class OutageWatch {
 public:
  OutageWatch(double start_s, double end_s) : start_s_(start_s), end_s_(end_s) {}

  void observe(double t, double error_m, bool ok, long gnss_fused) {
    if (t < start_s_) {
      f_.error_before_m = error_m;
      return;
    }
    if (returned_) return;
    if (t > end_s_ && gnss_fused > fused_at_end_) {  // a fix fused again: the drift ended before it
      returned_ = true;
      f_.fix_gone_s = t - start_s_;
      return;
    }
    f_.drift_m = std::max(f_.drift_m, error_m);
    f_.ok_through_outage = f_.ok_through_outage && ok;
    if (t <= end_s_) fused_at_end_ = gnss_fused;
  }
  void step(double t, double step_m, bool fixed) {
    if (!(t > end_s_ && t < end_s_ + 30.0)) return;
    f_.return_step_m = std::max(f_.return_step_m, step_m);
    if (fixed && !fixed_seen_) f_.fixed_return_step_m = step_m;
    fixed_seen_ = fixed_seen_ || fixed;
  }
  const OutageFigures& figures() const { return f_; }

 private:
  double start_s_, end_s_;
  OutageFigures f_;
  long fused_at_end_ = 0;
  bool returned_ = false, fixed_seen_ = false;
};

/// What the rover's owner does before relying on the encoders (the paper measured its 1.8 mm per pulse): drives
/// `straight_m` / 2 straight on the same ground and divides the RTK receiver's fixed travel by the pulses counted.
/// The wheels roll on a slightly smaller radius than their nominal one (the tyres sink into the contact), so the
/// nominal figure over-counts by a few percent.
double calibrateMetresPerPulse(const FieldLoopConfig& c) {
  RoverSim sim(loopSimParams(c));
  RoverSensorParams sp;
  sp.seed = c.seed + 1000u;
  sp.gnss.seed = c.seed + 1000u;
  RoverSensors sensors(sim, sp);
  const double dt = sim.params().timestep_s, drive_start = sim.time() + c.wait_for_fix_s;
  std::optional<Eigen::Vector3d> first, last;
  std::int32_t first_pulses = 0, last_pulses = 0, pulses = 0;
  double travelled = 0.0, stopped = -1.0;
  RoverPose2d previous = sensors.truthPose();
  while (stopped < 0.0 || sim.time() < stopped + 3.0) {
    const double t = sim.time();
    const RoverPose2d now = sensors.truthPose();
    travelled += std::hypot(now.x - previous.x, now.y - previous.y);
    previous = now;
    const bool go = t >= drive_start && travelled < 0.5 * c.straight_m;
    if (t >= drive_start && !go && stopped < 0.0) stopped = t;
    sim.setSwashplatePwm(go ? c.pwm : 90.0);
    if (t - drive_start > c.time_limit_s) throw std::runtime_error("field loop: calibration drive did not end");
    sim.advance(dt);
    const RoverSensorFrame f = sensors.poll();
    if (f.wheels) pulses = f.wheels->left_pulses + f.wheels->right_pulses;
    for (const GnssReading& g : f.gnss) {
      if (g.solution.state != thorvald_sim::GnssFixState::kFixed) continue;
      if (sim.time() < drive_start) first = g.solution.enu_m, first_pulses = pulses;
      if (stopped >= 0.0) last = g.solution.enu_m, last_pulses = pulses;
    }
  }
  const double per_pulse = sim.params().drive.metres_per_pulse;
  if (!first || !last || last_pulses <= first_pulses) return per_pulse;
  return (*last - *first).head<2>().norm() / (0.5 * (last_pulses - first_pulses));
}

// One sensor frame into one filter; the watched filter's GNSS steps and errors go to the outage watch.
void feedFilter(const RoverSensorFrame& f, RoverFusion& fu, OutageWatch* watch, double now, const RoverPose2d& truth,
                const RoverPose2d& start) {
  if (f.wheels) fu.onWheels(*f.wheels);
  for (const ImuReading& imu : f.imu) fu.onImu(imu);
  for (const GnssReading& g : f.gnss) {
    const RoverPose2d before = fu.estimate(g.solution.time_s);
    fu.onGnss(g);
    const RoverPose2d after = fu.estimate(g.solution.time_s);
    if (watch)
      watch->step(g.solution.time_s, std::hypot(after.x - before.x, after.y - before.y),
                  g.solution.state == thorvald_sim::GnssFixState::kFixed);
  }
  if (watch && (f.wheels || !f.gnss.empty()))
    watch->observe(now, errorOf(fu.estimate(now), truth, start).norm(), fu.health(now).localization_ok, fu.gnssFused());
}

Table1Row table1Row(RoverFusion& fu, double t_end, const RoverPose2d& truth, const RoverPose2d& start) {
  Table1Row row;
  row.set = fu.set();
  const Eigen::Vector2d e = errorOf(fu.estimate(t_end), truth, start);
  row.error_x_m = std::abs(e.x());
  row.error_y_m = std::abs(e.y());
  row.error_m = e.norm();
  const Eigen::Vector2d s = fu.positionSigma();
  row.sigma_x_m = s.x();
  row.sigma_y_m = s.y();
  row.localization_ok = fu.health(t_end).localization_ok;
  return row;
}

}  // namespace

FieldLoopResult runFieldLoop(const FieldLoopConfig& c) {
  const auto wall_start = std::chrono::steady_clock::now();
  RoverSim sim(loopSimParams(c));
  RoverSensorParams sp;
  sp.seed = c.seed;
  sp.gnss.seed = c.seed;
  sp.second_gnss = true;
  const double drive_start = sim.time() + c.wait_for_fix_s;
  if (c.outage_s > 0.0)
    sp.gnss.outages.push_back({drive_start + c.outage_start_s, drive_start + c.outage_start_s + c.outage_s});
  RoverSensors sensors(sim, sp);
  std::vector<std::unique_ptr<RoverFusion>> filters;
  RoverFusionParams fp = c.fusion;
  fp.axle_to_joint_m = sim.params().geometry.axle_to_joint_m;
  fp.metres_per_pulse = c.calibrate_odometry ? calibrateMetresPerPulse(c) : sim.params().drive.metres_per_pulse;
  for (SensorSet s : c.sets)
    filters.push_back(std::make_unique<RoverFusion>(
        s, fp, std::vector<Eigen::Vector3d>{sensors.antennaInBase(0), sensors.antennaInBase(1)}));
  int watched = -1;
  for (size_t i = 0; i < filters.size() && watched < 0; ++i)
    if (gnssReceiversOf(filters[i]->set()) > 0) watched = static_cast<int>(i);
  std::optional<OutageWatch> watch;
  if (c.outage_s > 0.0 && watched >= 0)
    watch.emplace(drive_start + c.outage_start_s, drive_start + c.outage_start_s + c.outage_s);

  const RoverPose2d start = sensors.truthPose();
  LoopDriver driver(c, start);
  const double dt = sim.params().timestep_s;
  bool driving = true;
  std::optional<WheelReading> last_wheels;
  double stopped_at = 0.0, articulation = 0.0;
  while (true) {
    const double t = sim.time();
    if (t >= drive_start) {
      double pwm = 90.0, art = 0.0;
      if (driving) {
        driving = driver.command(sensors.truthPose(), &pwm, &art);
        if (!driving) stopped_at = t;
      }
      sim.setSwashplatePwm(driving ? pwm : 90.0);
      // The valve moves the cylinders at their rate (relays on), not in one step.
      const double rate = sim.params().drive.articulation_rate_deg_per_s * dt;
      articulation = std::clamp(art, articulation - rate, articulation + rate);
      sim.setArticulationDeg(articulation);
      if (!driving && t > stopped_at + 3.0) break;
      if (t - drive_start > c.time_limit_s) throw std::runtime_error("field loop: not closed within the time limit");
    }
    sim.advance(dt);
    const RoverSensorFrame f = sensors.poll();
    if (f.wheels) last_wheels = f.wheels;
    for (size_t i = 0; i < filters.size(); ++i)
      feedFilter(f, *filters[i], static_cast<int>(i) == watched && watch ? &*watch : nullptr, sim.time(),
                 sensors.truthPose(), start);
  }
  FieldLoopResult out;
  const double t_end = sim.time();
  const RoverPose2d truth = sensors.truthPose();
  for (auto& fu : filters) out.rows.push_back(table1Row(*fu, t_end, truth, start));
  if (watch) out.outage = watch->figures();
  out.metres_per_pulse = fp.metres_per_pulse;
  out.loop_length_m = driver.travelled();
  if (last_wheels) {
    out.encoder_travel_m = 0.5 * (last_wheels->left_pulses + last_wheels->right_pulses) * fp.metres_per_pulse;
  }
  out.closure_gap_m = std::hypot(truth.x - start.x, truth.y - start.y);
  out.drive_s = t_end - drive_start;
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return out;
}

}  // namespace sim
}  // namespace cotton_harvester
