#pragma once

#include <string>
#include <vector>

#include "thorvald_base/odometry_integrator.h"
#include "thorvald_base/robot_config.h"
#include "thorvald_base/simulated_drive.h"
#include "thorvald_base/twist2d.h"

namespace thorvald_base {

/// One constant command held for a while.
struct TwistSegment {
  double duration_s;
  Twist2D twist;
};

/// The paper's odometry test (§3.3.2): 77 s of commands in x, y and yaw, about 80 m, that would close a loop if
/// the robot followed them exactly (straights, half circles, crab moves, a diagonal out and back). The simulated
/// robot does not close it: it loses part of each turn while its wheels steer, as a real one does.
std::vector<TwistSegment> paperLoop();

/// How each drive's readings are corrupted in a trial.
struct TrialCorruption {
  double speed_noise_radps = 0.02;
  double steering_noise_rad = 0.003;
  std::vector<int> radius_error_drives = {1, 4};  ///< these wheels are 1% larger than the robot file says
  double radius_error = 0.01;
  int slipping_drive = 2;  ///< this wheel reads faster than it rolls part of the time
  double slip_ratio = 0.15;
  double slip_fraction = 0.3;
};

/// A path sample: time and the three poses.
struct TrialSample {
  double t;
  Pose2D truth, least_squares, paper;
};

/// Result of one trial.
struct TrialResult {
  double distance_truth_m = 0, distance_ls_m = 0, distance_paper_m = 0;
  double end_error_ls_m = 0, end_error_paper_m = 0;
  std::vector<TrialSample> path;  ///< every 0.1 s
  double errorPctLs() const { return 100.0 * end_error_ls_m / distance_truth_m; }
  double errorPctPaper() const { return 100.0 * end_error_paper_m / distance_truth_m; }
};

/// Drives `robot` through `loop` on the internal joint simulator at `rate_hz`, with readings corrupted as
/// `corruption` says (seeded by `seed`), and integrates three odometries side by side: the truth (least-squares
/// fit of the ideal joints' true rolling), the least-squares estimator and the paper's random-pairs estimator,
/// both reading the same corrupted joint states.
TrialResult runOdometryTrial(const RobotConfig& robot, const std::vector<TwistSegment>& loop,
                             const TrialCorruption& corruption, unsigned seed, double rate_hz = 50.0);

/// A drive with the keys of a standard Thorvald drive module (Figure 5: r_wheel 0.2 m, gear ratio 42, 1024 ppr,
/// 3000 rpm, steering ratio 42.857, limit 3.078 rad) at (x, y) [m], node index + 1.
DriveConfig thorvaldDriveModule(int index, double x, double y, int type = 0);

/// The asymmetric six-wheel-drive, six-wheel-steering robot of the Thorvald paper's Figure 7.
RobotConfig figure7Robot();

}  // namespace thorvald_base
