// rostest of rail_detector: started by its launch file; the test publishes the camera's tf and synthetic
// clouds and checks the status, the pose and the mount calibration service.
#include <cmath>
#include <cstdio>
#include <limits>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <std_msgs/Bool.h>
#include <ros/ros.h>
#include <thorvald_common/ros/wait_for.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "../src/nodes/cloud_messages.h"
#include "greenhouse_rail_nav/RailDetectionStatus.h"
#include "greenhouse_rail_nav/mount_calibration.h"
#include "greenhouse_rail_nav/testing/synthetic_depth_cloud.h"

using namespace greenhouse_rail_nav;
using StatusMsg = greenhouse_rail_nav::RailDetectionStatus;

namespace {

const char* kCameraFrame = "camera_depth_optical_frame";

class RailDetectorNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    status_sub_ = nh_.subscribe<StatusMsg>("rail_detection", 20,
                                           [this](const StatusMsg::ConstPtr& m) { statuses_.push_back(m); });
    pose_sub_ = nh_.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
        "rail_pose", 20, [this](const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) { poses_.push_back(m); });
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("camera/depth/points", 2);
    // The camera's nominal mount, as robot_state_publisher would give it.
    const Eigen::Isometry3d mount = opticalFrameInBase(0.35, 0.0, 0.70, 0.70);
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "base_link";
    t.child_frame_id = kCameraFrame;
    t.transform.translation.x = mount.translation().x();
    t.transform.translation.y = mount.translation().y();
    t.transform.translation.z = mount.translation().z();
    const Eigen::Quaterniond q(mount.linear());
    t.transform.rotation.x = q.x();
    t.transform.rotation.y = q.y();
    t.transform.rotation.z = q.z();
    t.transform.rotation.w = q.w();
    tf_broadcaster_.sendTransform(t);
    ASSERT_TRUE(waitFor([this] { return cloud_pub_.getNumSubscribers() > 0 && status_sub_.getNumPublishers() > 0; }));
  }

  template <typename F>
  bool waitFor(F condition, double timeout_s = 20.0) {
    return thorvald_common::waitFor(condition, timeout_s);
  }

  /// Publishes a cloud and returns the status the node answers it with (matched by stamp).
  StatusMsg::ConstPtr send(sensor_msgs::PointCloud2 cloud) {
    stamp_ = std::max(ros::Time::now(), stamp_ + ros::Duration(0.001));
    cloud.header.stamp = stamp_;
    cloud_pub_.publish(cloud);
    StatusMsg::ConstPtr answer;
    waitFor([&] {
      for (const auto& s : statuses_)
        if (s->header.stamp == stamp_) answer = s;
      return answer != nullptr;
    });
    return answer;
  }

  sensor_msgs::PointCloud2 render(const thorvald_base::Pose2D& base_in_rail, std::uint32_t seed,
                                  const Eigen::Isometry3d& true_mount = opticalFrameInBase(0.35, 0.0, 0.70, 0.70)) {
    DepthSceneParams scene;
    scene.seed = seed;
    scene.camera_in_base = true_mount;
    return toMessage(renderDepthCloud(scene, base_in_rail), kCameraFrame, ros::Time::now());
  }

  /// Sends the cloud until the node has the camera's tf (the static tf may arrive after the first cloud).
  StatusMsg::ConstPtr sendOnceTfIsKnown(const sensor_msgs::PointCloud2& cloud) {
    StatusMsg::ConstPtr answer;
    waitFor([&] {
      answer = send(cloud);
      return answer && answer->status != StatusMsg::NO_TRANSFORM;
    });
    return answer;
  }

  ros::NodeHandle nh_;
  ros::Subscriber status_sub_, pose_sub_;
  ros::Publisher cloud_pub_;
  tf2_ros::StaticTransformBroadcaster tf_broadcaster_;
  std::vector<StatusMsg::ConstPtr> statuses_;
  std::vector<geometry_msgs::PoseWithCovarianceStamped::ConstPtr> poses_;
  ros::Time stamp_;
};

}  // namespace

TEST_F(RailDetectorNodeTest, PublishesThePoseInTheRailFrame) {
  const thorvald_base::Pose2D truth(-0.76, 0.04, -0.02);
  const auto status = sendOnceTfIsKnown(render(truth, 3));
  ASSERT_TRUE(status);
  ASSERT_EQ(status->status, StatusMsg::FOUND) << status->reason;
  // 3 cm / 0.02 rad / 0.15 m as in the library tests.
  EXPECT_NEAR(status->y, truth.y, 0.03);
  EXPECT_NEAR(status->yaw, truth.yaw, 0.02);
  EXPECT_NEAR(status->x, truth.x, 0.15);
  ASSERT_TRUE(waitFor([&] { return !poses_.empty() && poses_.back()->header.stamp == status->header.stamp; }));
  const auto& pose = *poses_.back();
  EXPECT_EQ(pose.header.frame_id, "rail");
  EXPECT_NEAR(pose.pose.pose.position.y, truth.y, 0.03);
  EXPECT_GE(pose.pose.covariance[7], 0.02 * 0.02);
  EXPECT_GE(pose.pose.covariance[35], 0.014 * 0.014);
}

TEST_F(RailDetectorNodeTest, RejectsBadCloudsAndLivesOn) {
  ASSERT_TRUE(sendOnceTfIsKnown(render(thorvald_base::Pose2D(-0.8, 0.0, 0.0), 4)));
  OrganisedCloud empty;
  auto status = send(toMessage(empty, kCameraFrame, ros::Time::now()));
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, StatusMsg::BAD_INPUT) << status->reason;

  OrganisedCloud nan_cloud;
  nan_cloud.width = 640;
  nan_cloud.height = 480;
  nan_cloud.points.assign(640 * 480, Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  status = send(toMessage(nan_cloud, kCameraFrame, ros::Time::now()));
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, StatusMsg::BAD_INPUT);
  EXPECT_NE(status->reason.find("no finite point"), std::string::npos) << status->reason;

  OrganisedCloud tiny;
  tiny.width = 2;
  tiny.height = 1;
  tiny.points = {Eigen::Vector3f(0.0f, 0.3f, 1.0f), Eigen::Vector3f(0.1f, 0.3f, 1.0f)};
  status = send(toMessage(tiny, kCameraFrame, ros::Time::now()));
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, StatusMsg::NOT_FOUND) << status->reason;

  auto no_tf = toMessage(tiny, "frame_nobody_publishes", ros::Time::now());
  status = send(no_tf);
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, StatusMsg::NO_TRANSFORM) << status->reason;

  auto malformed = toMessage(tiny, kCameraFrame, ros::Time::now());
  malformed.fields.pop_back();  // no z
  status = send(malformed);
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, StatusMsg::BAD_INPUT);
  EXPECT_NE(status->reason.find("malformed"), std::string::npos) << status->reason;

  auto truncated = render(thorvald_base::Pose2D(-0.8, 0.0, 0.0), 5);
  truncated.data.resize(truncated.data.size() / 2);
  status = send(truncated);
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, StatusMsg::BAD_INPUT);

  // Still working.
  status = send(render(thorvald_base::Pose2D(-0.8, 0.0, 0.0), 6));
  ASSERT_TRUE(status);
  EXPECT_TRUE(status->status == StatusMsg::FOUND || status->status == StatusMsg::HELD_BACK) << status->reason;
}

TEST_F(RailDetectorNodeTest, MountCalibrationIsComputedAppliedAndPersisted) {
  ros::NodeHandle pnh("~");
  std::string calibration_file;
  ASSERT_TRUE(pnh.getParam("calibration_file", calibration_file));
  // The real camera sits 2 cm to the left and turned 0.04 rad; the tf says it is straight.
  const Eigen::Isometry3d true_mount = opticalFrameInBase(0.35, 0.02, 0.70, 0.70, 0.04);
  auto status =
      sendOnceTfIsKnown(render(thorvald_base::Pose2D(1.0, 0.0, 0.0), 7, true_mount));  // standing on the rails
  ASSERT_TRUE(status);
  ASSERT_TRUE(status->status == StatusMsg::FOUND || status->status == StatusMsg::HELD_BACK) << status->reason;
  ros::ServiceClient client = nh_.serviceClient<std_srvs::Trigger>("rail_detector/calibrate_mount");
  ASSERT_TRUE(client.waitForExistence(ros::Duration(10.0)));
  std_srvs::Trigger call;
  ASSERT_TRUE(client.call(call));
  ASSERT_TRUE(call.response.success) << call.response.message;
  MountCorrection stored;
  std::string error;
  ASSERT_TRUE(loadMountCorrection(calibration_file, &stored, &error)) << error;
  EXPECT_NEAR(stored.yaw_rad, 0.04, 0.01);  // rails seen turned -0.04 rad: turn them back

  // In front of the rails, the corrected estimate is within tolerance of the truth.
  const thorvald_base::Pose2D truth(-0.75, -0.03, 0.02);
  status = send(render(truth, 8, true_mount));
  ASSERT_TRUE(status);
  ASSERT_EQ(status->status, StatusMsg::FOUND) << status->reason;
  EXPECT_NEAR(status->y, truth.y, 0.03);
  EXPECT_NEAR(status->yaw, truth.yaw, 0.02);
  std::remove(calibration_file.c_str());
}

// ~enable false: the node leaves the cloud topic (a camera publishing only to subscribers stops); true: it detects
// again.
TEST_F(RailDetectorNodeTest, EnableSwitchesTheCloudSubscriptionOffAndOn) {
  ros::Publisher enable = nh_.advertise<std_msgs::Bool>("rail_detector/enable", 1, true);
  ASSERT_TRUE(waitFor([&] { return enable.getNumSubscribers() > 0; }));
  std_msgs::Bool b;
  b.data = false;
  enable.publish(b);
  EXPECT_TRUE(waitFor([&] { return cloud_pub_.getNumSubscribers() == 0; }, 10.0)) << "still subscribed when off";
  b.data = true;
  enable.publish(b);
  ASSERT_TRUE(waitFor([&] { return cloud_pub_.getNumSubscribers() > 0; }, 10.0)) << "not subscribed again when on";
  const auto status = sendOnceTfIsKnown(render(thorvald_base::Pose2D(-0.76, 0.02, 0.01), 5));
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, StatusMsg::FOUND) << status->reason;
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rail_detector_node_test");
  return RUN_ALL_TESTS();
}
