// base_driver as a user runs it: robot file in the namespace, commands on twist_mux/cmd_vel, odometry out.
#include <geometry_msgs/Twist.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <thorvald_common/ros/wait_for.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include <cmath>
#include <functional>

#include "thorvald_base/BaseState.h"
#include "thorvald_base/SetDriveParams.h"

namespace {

class Base {
 public:
  Base() {
    cmd_ = nh_.advertise<geometry_msgs::Twist>("twist_mux/cmd_vel", 10);
    odom_sub_ = nh_.subscribe("odometry/base_raw", 10, &Base::onOdom, this);
    state_sub_ = nh_.subscribe("base_state", 10, &Base::onState, this);
    joint_sub_ = nh_.subscribe("joint_states", 10, &Base::onJoints, this);
  }

  /// Spins until `done` holds or `timeout_s` passes; returns whether it held.
  bool waitFor(const std::function<bool()>& done, double timeout_s) {
    return thorvald_common::waitFor(done, timeout_s, thorvald_common::spinEvery(0.002));
  }

  /// Publishes `cmd` at 20 Hz for `seconds` (or until `each` returns false), then one zero command as a user's
  /// teleop or planner does when it stops.
  void drive(
      double vx, double vy, double wz, double seconds, const std::function<bool()>& each = [] { return true; }) {
    geometry_msgs::Twist t;
    t.linear.x = vx;
    t.linear.y = vy;
    t.angular.z = wz;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    ros::WallTime next = ros::WallTime::now();
    while (ros::ok() && ros::WallTime::now() < end) {
      if (ros::WallTime::now() >= next) {
        cmd_.publish(t);
        next += ros::WallDuration(0.05);
      }
      ros::spinOnce();
      if (!each()) break;
      ros::WallDuration(0.002).sleep();
    }
    cmd_.publish(geometry_msgs::Twist());
  }

  /// Waits until the base stands still, then zeroes odometry.
  void resetAtRest() {
    ASSERT_TRUE(waitFor([&] { return cmd_.getNumSubscribers() > 0; }, 5.0));
    ASSERT_TRUE(waitFor(
        [&] {
          return have_odom_ && std::fabs(odom_.twist.twist.linear.x) < 1e-4 &&
                 std::fabs(odom_.twist.twist.linear.y) < 1e-4 && std::fabs(odom_.twist.twist.angular.z) < 1e-4;
        },
        10.0));
    std_srvs::Trigger t;
    ASSERT_TRUE(ros::service::call("base_driver/reset_base_odom", t));
    const auto stamp = ros::Time::now();
    ASSERT_TRUE(waitFor([&] { return odom_.header.stamp > stamp && std::fabs(odom_.pose.pose.position.x) < 1e-9; }, 5));
  }

  double yaw() const { return 2.0 * std::atan2(odom_.pose.pose.orientation.z, odom_.pose.pose.orientation.w); }

  ros::NodeHandle nh_;
  ros::Publisher cmd_;
  ros::Subscriber odom_sub_, state_sub_, joint_sub_;
  nav_msgs::Odometry odom_;
  thorvald_base::BaseState state_;
  sensor_msgs::JointState joints_;
  bool have_odom_ = false;

 private:
  void onOdom(const nav_msgs::Odometry& m) {
    odom_ = m;
    have_odom_ = true;
  }
  void onState(const thorvald_base::BaseState& m) { state_ = m; }
  void onJoints(const sensor_msgs::JointState& m) { joints_ = m; }
};

bool within(double value, double want, double rel) { return std::fabs(value - want) <= rel * std::fabs(want); }

/// Drives `cmd` and checks that, once the wheels have reached their angles, the odometry twist settles within 1%
/// of it in under 1 s. Returns the time spent after settling.
void expectSettles(
    Base& base, double vx, double vy, double wz, double seconds,
    const std::function<bool()>& until = [] { return true; }) {
  ros::WallTime reached, settled;
  std::vector<double> last_steer;
  base.drive(vx, vy, wz, seconds, [&] {
    const auto& s = base.state_;
    if (s.drives.empty()) return true;
    bool all = true;
    for (const auto& d : s.drives) all = all && std::fabs(d.steering - d.steering_cmd) < 0.01;
    if (all && reached.isZero()) reached = ros::WallTime::now();
    if (!all) reached = ros::WallTime();
    const auto& t = base.odom_.twist.twist;
    const bool ok = within(t.linear.x, vx, 0.01) && within(t.linear.y, vy, 0.01) && within(t.angular.z, wz, 0.01) &&
                    std::fabs(t.linear.x - vx) < 0.01 * std::max(1e-3, std::hypot(vx, vy)) + 1e-3 &&
                    std::fabs(t.linear.y - vy) < 0.01 * std::max(1e-3, std::hypot(vx, vy)) + 1e-3;
    if (ok && settled.isZero() && !reached.isZero()) settled = ros::WallTime::now();
    return until();
  });
  ASSERT_FALSE(reached.isZero()) << "wheels never reached their angles";
  ASSERT_FALSE(settled.isZero()) << "odometry never settled to the command";
  EXPECT_LT((settled - reached).toSec(), 1.0);
}

}  // namespace

TEST(BaseDriverNode, StraightLineOneMetre) {
  Base base;
  base.resetAtRest();
  base.drive(0.1, 0.0, 0.0, 10.0);
  ASSERT_TRUE(base.waitFor([&] { return std::fabs(base.odom_.twist.twist.linear.x) < 1e-4; }, 5.0));
  EXPECT_NEAR(base.odom_.pose.pose.position.x, 1.00, 0.01);
  EXPECT_NEAR(base.odom_.pose.pose.position.y, 0.0, 0.005);
  EXPECT_EQ(base.odom_.header.frame_id, "thorvald_001/odom");
  EXPECT_EQ(base.odom_.child_frame_id, "thorvald_001/base_link");
  ASSERT_EQ(base.joints_.name.size(), 8u);
  EXPECT_EQ(base.joints_.name[0], "thorvald_001/steering0");
  EXPECT_EQ(base.joints_.name[1], "thorvald_001/wheel0");
}

TEST(BaseDriverNode, TurnInPlace) {
  Base base;
  base.resetAtRest();
  expectSettles(base, 0.0, 0.0, M_PI / 10, 4.0);
  EXPECT_LT(std::hypot(base.odom_.pose.pose.position.x, base.odom_.pose.pose.position.y), 0.01);
  EXPECT_GT(base.yaw(), 0.5 * M_PI / 10 * 3.0);  // most of 4 s of turning, after the wheels turned
}

TEST(BaseDriverNode, CrabMove) {
  Base base;
  base.resetAtRest();
  expectSettles(base, 0.0, 0.2, 0.0, 3.0);
  EXPECT_NEAR(base.odom_.pose.pose.position.x, 0.0, 0.01);
  EXPECT_GT(base.odom_.pose.pose.position.y, 0.4);
  EXPECT_NEAR(base.yaw(), 0.0, 0.01);
}

TEST(BaseDriverNode, HalfCircle) {
  Base base;
  base.resetAtRest();
  // Radius 1 m: v = 0.5 m/s, w = 0.5 rad/s; half a circle takes pi s once the wheels have turned.
  expectSettles(base, 0.5, 0.0, 0.5, 10.0, [&] { return std::fabs(base.yaw()) < M_PI - 0.05; });
  ASSERT_TRUE(base.waitFor([&] { return std::fabs(base.odom_.twist.twist.linear.x) < 1e-4; }, 5.0));
  // The robot stays on the circle about (0, 1): odometry matches the commanded motion.
  const auto& p = base.odom_.pose.pose.position;
  EXPECT_NEAR(std::hypot(p.x, p.y - 1.0), 1.0, 0.03);
  EXPECT_GT(std::fabs(base.yaw()), 2.5);
}

TEST(BaseDriverNode, OneCommandThenSilenceStopsShort) {
  Base base;
  base.resetAtRest();
  base.drive(0.05, 0.0, 0.0, 1.0);  // wheels straight first, so the one command is not spent steering
  base.resetAtRest();
  geometry_msgs::Twist t;
  t.linear.x = 1.0;
  ASSERT_TRUE(base.waitFor([&] { return base.cmd_.getNumSubscribers() > 0; }, 5.0));
  base.cmd_.publish(t);
  ASSERT_TRUE(base.waitFor([&] { return base.odom_.twist.twist.linear.x > 0.1; }, 2.0));
  ASSERT_TRUE(base.waitFor([&] { return std::fabs(base.odom_.twist.twist.linear.x) < 1e-4; }, 5.0));
  EXPECT_LT(base.odom_.pose.pose.position.x, 0.8);
  EXPECT_TRUE(base.waitFor([&] { return base.state_.command_timed_out; }, 1.0));
}

TEST(BaseDriverNode, NanCommandMovesNothing) {
  Base base;
  base.resetAtRest();
  base.drive(NAN, 0.0, 0.0, 1.0);
  base.drive(0.0, INFINITY, NAN, 0.5);
  const auto& o = base.odom_;
  EXPECT_EQ(o.pose.pose.position.x, 0.0);
  EXPECT_EQ(o.pose.pose.position.y, 0.0);
  for (double v : {o.pose.pose.position.x, o.pose.pose.orientation.w, o.twist.twist.linear.x, o.twist.twist.angular.z})
    EXPECT_TRUE(std::isfinite(v));
  for (double c : o.pose.covariance) EXPECT_TRUE(std::isfinite(c));
  for (double c : o.twist.covariance) EXPECT_TRUE(std::isfinite(c));
}

TEST(BaseDriverNode, SafetyStopHolds) {
  Base base;
  base.resetAtRest();
  std_srvs::SetBool stop;
  stop.request.data = true;
  ASSERT_TRUE(ros::service::call("base_driver/safety_stop", stop));
  base.drive(0.3, 0.0, 0.0, 1.5);
  EXPECT_LT(std::fabs(base.odom_.pose.pose.position.x), 1e-3);
  EXPECT_TRUE(base.state_.safety_stop);
  stop.request.data = false;
  ASSERT_TRUE(ros::service::call("base_driver/safety_stop", stop));
  base.drive(0.3, 0.0, 0.0, 1.0);
  EXPECT_GT(base.odom_.pose.pose.position.x, 0.1);
}

TEST(BaseDriverNode, WheelRadiusChange) {
  Base base;
  base.resetAtRest();
  // From floor wheels (0.2 m) to rail wheels of 0.12 m on every drive.
  thorvald_base::SetDriveParams srv;
  thorvald_base::DriveParam p;
  p.drive = -1;
  p.key = "r_wheel";
  p.value = 0.12;
  srv.request.params.push_back(p);
  ASSERT_TRUE(ros::service::call("base_driver/set_drive_params", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  ASSERT_TRUE(base.waitFor([&] { return !base.state_.drives.empty() && base.state_.drives[0].r_wheel == 0.12; }, 2));
  const double wheel0 = base.joints_.position[1];
  base.drive(0.2, 0.0, 0.0, 3.0);
  ASSERT_TRUE(base.waitFor([&] { return std::fabs(base.odom_.twist.twist.linear.x) < 1e-4; }, 5.0));
  const double distance = base.odom_.pose.pose.position.x;
  EXPECT_NEAR(distance, 0.6, 0.01);
  // The same distance now takes 0.2/0.12 times the wheel turns.
  EXPECT_NEAR(base.joints_.position[1] - wheel0, distance / 0.12, 0.05);
  srv.request.params[0].value = -1.0;
  ASSERT_TRUE(ros::service::call("base_driver/set_drive_params", srv));
  EXPECT_FALSE(srv.response.success);
  srv.request.params[0].value = 0.2;
  ASSERT_TRUE(ros::service::call("base_driver/set_drive_params", srv));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "base_driver_node_test");
  ros::NodeHandle nh;
  if (!ros::service::waitForService("base_driver/reset_base_odom", ros::Duration(20))) return 1;
  return RUN_ALL_TESTS();
}
