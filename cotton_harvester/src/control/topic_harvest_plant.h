#pragma once

// The harvest machine's plant on ROS topics: frames from perception, the rover through its position
// target, the arm through the manipulator node. Waits are condition waits with deadlines on ROS time
// that poll the machine's preemption flag.

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
#include "cotton_harvester/control/harvest_machine.h"
#include "cotton_harvester/control/leaf_clearance.h"

namespace cotton_harvester {
namespace control {

struct TopicPlantParams {
  double observe_timeout_s = 3.0;   ///< wait for a fresh frame at most this long
  double settle_s = 0.3;            ///< frames must be this much newer than the end of the last action
  double effector_max_age_s = 0.5;  ///< wait at most this long (ROS time) for the frame's own end effector
  /// The end effector must come from the frame the bolls came from (perception stamps both with the image's
  /// stamp); an older frame's may show the arm where it was before its last move.
  double effector_stamp_tolerance_s = 0.001;
  /// When perception does not report the housing in a frame, the arm's calibrated position stands in: where
  /// `manipulator/joint_states` (closest to the frame's stamp, within joint_max_age_s) puts the housing's top face,
  /// camera-frame (extension + arm_extension_zero_x_m, arm_y_m, depth).
  bool effector_from_calibration = false;
  double joint_max_age_s = 0.15;
  double arm_y_m = 0.0;  ///< camera-frame y of the housing's centre (the arm's plane) [m]
  /// The arm's travel (the manipulator's calibration limits): targets are clamped into it, so a move the
  /// manipulator would clamp is waited for where the axis can go [m].
  double horizontal_min_m = 0.0, horizontal_max_m = 0.70;
  double vertical_min_m = 0.30, vertical_max_m = 1.93;
  /// The vacuum stays on while the arm retracts from the boll (a boll caught late still follows the nozzle).
  bool vacuum_while_retracting = true;
  double rover_tolerance_m = 0.05;  ///< a rover move is done within this of its target ...
  double rover_settle_s = 0.5;      ///< ... held this long
  double rover_timeout_s = 20.0;    ///< plus rover_timeout_per_m_s per metre: then the move failed
  double rover_timeout_per_m_s = 20.0;
  double arm_tolerance_m = 0.01;  ///< an arm axis is there within this
  double arm_timeout_s = 15.0;
  double pick_dwell_s = 1.0;  ///< brush runs this long at the boll
  /// > 0: as a rover move starts, an end-effector deeper than this below the camera goes up to it, so the rover
  /// never drives with it in the plants; the move is done when the arm has arrived too [m]. 0: the arm stays.
  double rest_depth_m = 0.0;
  /// Before a pick, leaves over the boll along the approach (in the cloud of the frame the decision used,
  /// `camera/depth/points`) are swept aside and the boll located again in a new frame (LeafClearanceParams).
  bool clear_leaves_before_pick = false;
  LeafClearanceParams leaves;
  double arm_extension_zero_x_m = -0.55;  ///< camera-frame x of the housing's centre at extension 0 [m]
  /// Looking under the leaves when the machine asks (HarvestParams::search_under_leaves): the arm goes up to
  /// rest_depth_m (which must then be > 0: above the plants) and sweeps the layers of foliage in its strip of the
  /// cloud aside (CanopySearchParams). false: the machine's request finds nothing to sweep.
  bool search_under_leaves = false;
  CanopySearchParams canopy;
};

class TopicHarvestPlant : public HarvestPlant {
 public:
  TopicHarvestPlant(ros::NodeHandle& nh, const TopicPlantParams& params);

  std::optional<HarvestObservation> observe(const Preempted& preempted) override;
  MoveResult moveRover(double distance_m, const Preempted& preempted) override;
  MoveResult moveArmToDepth(double depth_m, const Preempted& preempted) override;
  MoveResult pick(double offset_m, const Preempted& preempted) override;
  std::optional<MoveResult> searchUnderLeaves(const Preempted& preempted) override;
  double now() const override { return ros::Time::now().toSec(); }
  double roverPositionM() const override;

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
  /// Points over the approach in the cloud of the frame last observed (0 without it).
  int pointsOverApproach(double from_x, double target_x, double depth_m) const;
  /// Sweeps the leaves over the boll aside and returns the pick's extension from a new frame (or target_ext).
  double clearAndRelocate(double target_ext, const Preempted& preempted, MoveResult* result);
  /// Waits until `done()` (called with the lock held) or the deadline; false on timeout/preemption.
  template <typename Done>
  bool waitFor(Done done, double timeout_s, const Preempted& preempted, bool* was_preempted);
  MoveResult moveArm(double extension_m, double depth_m, const Preempted& preempted);
  void markActionEnd();
  /// The current frame as an observation (mutex held); marks the frame used. `effector`: the frame's own.
  HarvestObservation makeObservation(const geometry_msgs::PointStamped::ConstPtr& effector);
  /// The frame's end effector among the last few reported (mutex held), or null.
  geometry_msgs::PointStamped::ConstPtr effectorOf(const ros::Time& stamp) const;
  /// Where the arm's calibration puts the housing at `stamp` (mutex held), from the joint states.
  std::optional<Point3> calibratedEffector(const ros::Time& stamp) const;

  TopicPlantParams params_;
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
  std::deque<sensor_msgs::PointCloud2::ConstPtr> clouds_;  ///< the last few, to find the observed frame's
  ros::Publisher rover_target_pub_, arm_target_pub_, brush_pub_;
  ros::Subscriber bolls_sub_, effector_sub_, rover_sub_, joints_sub_, busy_sub_, cloud_sub_;
  std::size_t picks_cleared_ = 0, picks_redetected_ = 0, leaf_searches_ = 0, leaf_sweeps_ = 0;

 public:
  /// Picks that swept leaves aside first, and of them those whose target a new frame corrected.
  std::size_t picksCleared() const { return picks_cleared_; }
  std::size_t picksRedetected() const { return picks_redetected_; }
  /// Places of the row where the arm looked under the leaves, and its sweeps there.
  std::size_t leafSearches() const { return leaf_searches_; }
  std::size_t leafSweeps() const { return leaf_sweeps_; }
};

}  // namespace control
}  // namespace cotton_harvester
