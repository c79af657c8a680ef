#include "thorvald_base/testing/odometry_trial.h"

#include <cmath>
#include <memory>

#include "thorvald_base/angles.h"
#include "thorvald_base/base_driver.h"
#include "thorvald_base/standard_calculator.h"

namespace thorvald_base {

std::vector<TwistSegment> paperLoop() {
  const double turn = kPi / 9.0;  // half a circle in 9 s
  return {
      {16.0, {1.2, 0.0, 0.0}},  {9.0, {1.05, 0.0, turn}}, {5.0, {0.0, 0.8, 0.0}}, {16.0, {1.2, 0.0, 0.0}},
      {9.0, {1.05, 0.0, turn}}, {5.0, {0.0, 0.8, 0.0}},   {8.5, {0.8, 0.4, 0.0}}, {8.5, {-0.8, -0.4, 0.0}},
  };
}

DriveConfig thorvaldDriveModule(int index, double x, double y, int type) {
  DriveConfig d;
  d.index = index;
  d.node = index + 1;
  d.x = x;
  d.y = y;
  d.type = type;
  d.r_wheel = 0.2;
  d.prp_gr_rt = 42;
  d.prp_enc_ppr = 1024;
  d.prp_max_rpm = 3000;
  d.prp_sim_a = 1.5;
  d.str_gr_rt = 42.8571429;
  d.str_enc_ppr = 1024;
  d.str_lim = 3.078027759;
  d.str_sim_v = 4.0;
  return d;
}

RobotConfig figure7Robot() {
  RobotConfig r;
  r.source = "figure 7 robot";
  r.base_calculator = kDefaultBaseCalculator;
  const double xy[6][2] = {{-0.9, -0.8}, {0.25, -0.8}, {1.1, -0.55}, {1.1, 0.75}, {0.1, 0.75}, {-0.9, 0.6}};
  for (int i = 0; i < 6; ++i) r.drives.push_back(thorvaldDriveModule(i, xy[i][0], xy[i][1]));
  return r;
}

namespace {

bool contains(const std::vector<int>& v, int x) {
  for (int e : v)
    if (e == x) return true;
  return false;
}

double endError(const Pose2D& a, const Pose2D& b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace

TrialResult runOdometryTrial(const RobotConfig& robot, const std::vector<TwistSegment>& loop,
                             const TrialCorruption& corruption, unsigned seed, double rate_hz) {
  std::vector<SimulatedDrive*> sims;
  std::vector<std::unique_ptr<MotorDrive>> drives;
  for (const auto& d : robot.drives) {
    SimulatedDriveOptions o;
    o.speed_noise_radps = corruption.speed_noise_radps;
    o.steering_noise_rad = corruption.steering_noise_rad;
    o.radius_error = contains(corruption.radius_error_drives, d.index) ? corruption.radius_error : 0.0;
    if (d.index == corruption.slipping_drive) {
      o.slip_ratio = corruption.slip_ratio;
      o.slip_fraction = corruption.slip_fraction;
    }
    o.seed = seed * 1000u + static_cast<unsigned>(d.index);
    auto sim = std::make_unique<SimulatedDrive>(d, o);
    sims.push_back(sim.get());
    drives.push_back(std::move(sim));
  }
  BaseDriverOptions options;
  options.calculator.estimator = "least_squares";
  BaseDriver driver(robot, std::make_unique<StandardCalculator>(), std::move(drives), {}, options);

  // The paper's estimator and the truth read the same drives through their own models.
  StandardCalculator paper;
  CalculatorOptions paper_options;
  paper_options.estimator = "random_pairs";
  paper_options.seed = seed;
  paper.configure(robot.drives, robot.passive_wheels, paper_options);
  LeastSquaresEstimator exact(1e9, 0);  // plain least squares: ideal joints agree, nothing to down-weight
  OdometryIntegrator paper_odom, truth_odom;
  Twist2D paper_prev, truth_prev;

  TrialResult result;
  const double dt = 1.0 / rate_hz;
  double t = 0.0, segment_end = 0.0;
  int step = 0;
  auto mean = [](const Twist2D& a, const Twist2D& b) {
    return Twist2D{0.5 * (a.vx + b.vx), 0.5 * (a.vy + b.vy), 0.5 * (a.wz + b.wz)};
  };
  std::vector<TwistSegment> plan = loop;
  plan.push_back({3.0, {}});  // come to rest
  for (const auto& seg : plan) {
    segment_end += seg.duration_s;
    for (; t < segment_end - 1e-9; t = (++step) * dt) {
      driver.setCommand(seg.twist, t);
      driver.update(t);
      const VelocityEstimate p = paper.estimateTwist(driver.feedback());
      std::vector<WheelObservation> ideal;
      for (size_t i = 0; i < sims.size(); ++i) {
        const DriveFeedback f = sims[i]->truth();
        const auto& d = robot.drives[i];
        ideal.push_back({d.x, d.y, f.steering_rad, f.wheel_speed_radps * d.r_wheel, true});
      }
      const VelocityEstimate tr = exact.estimate(ideal);
      if (step > 0) {
        paper_odom.integrate(mean(paper_prev, p.twist), p.covariance, dt);
        truth_odom.integrate(mean(truth_prev, tr.twist), tr.covariance, dt);
      }
      paper_prev = p.twist;
      truth_prev = tr.twist;
      if (step % static_cast<int>(std::max(1.0, std::round(0.1 * rate_hz))) == 0) {
        result.path.push_back({t, truth_odom.pose(), driver.odometry().pose(), paper_odom.pose()});
      }
    }
  }
  result.distance_truth_m = truth_odom.distance();
  result.distance_ls_m = driver.odometry().distance();
  result.distance_paper_m = paper_odom.distance();
  result.end_error_ls_m = endError(driver.odometry().pose(), truth_odom.pose());
  result.end_error_paper_m = endError(paper_odom.pose(), truth_odom.pose());
  return result;
}

}  // namespace thorvald_base
