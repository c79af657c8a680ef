#pragma once

// The harvest machine's plant on ROS topics: frames from perception (and their clouds), the rover through its
// position target, the arm and the vacuum through the manipulator node. Waits are condition waits with deadlines on
// ROS time that poll the machine's preemption flag.

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include <geometry_msgs/PointStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/control/canopy_search.h"
#include "cotton_harvester/control/harvest_plant.h"

namespace cotton_harvester {
namespace control {

/// How the plant talks to the nodes: waits, tolerances, where the end-effector comes from. How the arm picks, clears
/// leaves and rests is not here (HarvestActionParams, shared with the simulated rover).
struct TopicPlantParams {
  double observe_timeout_s = 3.0;   ///< wait for a fresh frame (and for its cloud) at most this long
  double settle_s = 0.3;            ///< frames must be this much newer than the end of the last action
  double effector_max_age_s = 0.5;  ///< wait at most this long (ROS time) for the frame's own end effector
  /// The end effector must come from the frame the bolls came from (perception stamps both with the image's
  /// stamp); an older frame's may show the arm where it was before its last move.
  double effector_stamp_tolerance_s = 0.001;
  /// When perception does not report the housing in a frame, the arm's calibrated position stands in: where
  /// `manipulator/joint_states` (closest to the frame's stamp, within joint_max_age_s) puts the housing's top face,
  /// camera-frame (extension + ArmWorkspace::extension_zero_x_m, ArmWorkspace::strip_y_m, depth).
  bool effector_from_calibration = false;
  double joint_max_age_s = 0.15;
  double rover_tolerance_m = 0.05;  ///< a rover move is done within this of its target ...
  double rover_settle_s = 0.5;      ///< ... held this long
  double rover_timeout_s = 20.0;    ///< plus rover_timeout_per_m_s per metre: then the move failed
  double rover_timeout_per_m_s = 20.0;
  double arm_tolerance_m = 0.01;  ///< an arm axis is there within this
  double arm_timeout_s = 15.0;
  /// Subscribe to `camera/depth/points` and keep the last few clouds (the node sets it when clearing leaves before
  /// a pick or looking under the leaves: 11 MB per frame at 1280 x 720).
  bool cloud = false;
};

/// The HarvestPlant primitives on ROS topics (see the file comment); the manoeuvres are HarvestActions.
class TopicHarvestPlant : public HarvestPlant {
 public:
  /// `arm`: the arm's calibration (HarvestActionParams::arm), for the end-effector's calibrated position.
  TopicHarvestPlant(ros::NodeHandle& nh, const TopicPlantParams& params, const ArmWorkspace& arm);

  std::optional<HarvestObservation> observe(const Preempted& preempted) override;
  MoveResult moveRover(double distance_m, const ArmPose& arm, const Preempted& preempted) override;
  MoveResult moveArm(const ArmPose& target, const Preempted& preempted) override;
  std::optional<ArmPose> armPose() const override;
  void setVacuum(bool on) override;
  MoveResult wait(double seconds, const Preempted& preempted) override;
  /// The cloud of the frame last observed, waited for up to observe_timeout_s (it may come a little after the
  /// frame's bolls); the focal length is read off the organised cloud.
  std::optional<CameraCloud> lastCloud(const Preempted& preempted) override;
  double now() const override { return ros::Time::now().toSec(); }
  double roverPositionM() const override;
  std::string lastFailure() const override;

  /// Frames dropped: NaN points, frames without an end effector close in time.
  std::size_t rejectedFrames() const;
  /// Observations whose end effector is the arm's calibrated position (perception did not report the housing).
  std::size_t effectorFromCalibration() const;
  /// True once the manipulator's joint states gave both axes.
  bool hasArmState() const;
  /// Checks the parameters; empty when sound, else "key: what is expected".
  static std::string check(const TopicPlantParams& params);

 private:
  void onBolls(const cotton_harvester::BollArray::ConstPtr& msg);
  void onEffector(const geometry_msgs::PointStamped::ConstPtr& msg);
  void onRoverPosition(const std_msgs::Float64::ConstPtr& msg);
  void onJoints(const sensor_msgs::JointState::ConstPtr& msg);
  void onBusy(const std_msgs::Bool::ConstPtr& msg);
  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg);
  /// The cloud of the frame last observed as a view into *keep (false without a usable one).
  bool observedCloud(sensor_msgs::PointCloud2::ConstPtr* keep, CloudView* view) const;
  /// Waits until `done()` (called with the lock held) or the deadline; false on timeout/preemption.
  template <typename Done>
  bool waitFor(Done done, double timeout_s, const Preempted& preempted, bool* was_preempted);
  /// Publishes the arm's target (NaN axes stay) and marks the arm busy until the manipulator reports otherwise.
  void commandArm(const ArmPose& target);
  /// The arm is at `target` and not busy (mutex held).
  bool armAt(const ArmPose& target) const;
  void markActionEnd();
  /// Logs a failed primitive and keeps it as the last failure (mutex held).
  void noteFailure(const std::string& what);
  /// The current frame as an observation (mutex held); marks the frame used. `effector`: the frame's own.
  HarvestObservation makeObservation(const geometry_msgs::PointStamped::ConstPtr& effector);
  /// The frame's end effector among the last few reported (mutex held), or null.
  geometry_msgs::PointStamped::ConstPtr effectorOf(const ros::Time& stamp) const;
  /// Where the arm's calibration puts the housing at `stamp` (mutex held), from the joint states.
  std::optional<Point3> calibratedEffector(const ros::Time& stamp) const;

  TopicPlantParams params_;
  ArmWorkspace arm_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  cotton_harvester::BollArray::ConstPtr bolls_;
  std::deque<geometry_msgs::PointStamped::ConstPtr> effectors_;  ///< the last few, to find a frame's own
  struct JointSample {
    ros::Time stamp;
    double extension_m, depth_m;
  };
  std::deque<JointSample> joint_history_;  ///< the last second or so of complete joint states
  std::size_t effector_from_calibration_ = 0;
  std::optional<double> rover_position_;
  std::optional<double> arm_extension_, arm_depth_;
  bool arm_busy_ = true;
  ros::Time action_end_;
  ros::Time last_used_stamp_;
  std::size_t rejected_frames_ = 0;
  std::string last_failure_;
  std::deque<sensor_msgs::PointCloud2::ConstPtr> clouds_;  ///< the last few, to find the observed frame's
  ros::Publisher rover_target_pub_, arm_target_pub_, brush_pub_;
  ros::Subscriber bolls_sub_, effector_sub_, rover_sub_, joints_sub_, busy_sub_, cloud_sub_;
};

}  // namespace control
}  // namespace cotton_harvester
