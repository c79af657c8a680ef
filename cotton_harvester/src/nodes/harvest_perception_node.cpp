// harvest_perception: finds the cotton bolls and the end-effector in the downward stereo camera's colour image,
// locates them in its organised point cloud and publishes them for the harvest state machine.

#include <map>
#include <memory>
#include <optional>
#include <string>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PointStamped.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/darknet_boll_detector.h"
#include "cotton_harvester/perception/network_boll_detector.h"
#include "cotton_harvester/perception/debug_overlay.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "perception_conversions.h"
#include "perception_params_ros.h"

namespace cotton_harvester {

using namespace perception;

/// Pairs each colour image with the organised cloud of the same instant (stamps within max_stamp_diff_s), runs
/// the pipeline and publishes. Single-threaded: all callbacks run on the global queue.
class HarvestPerceptionNode {
 public:
  HarvestPerceptionNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const PerceptionNodeConfig& config)
      : config_(config), pipeline_(config.pipeline, makeDetector(config)), image_transport_(nh), diagnostics_(nh, pnh) {
    bolls_pub_ = nh.advertise<BollArray>("bolls", 5);
    end_effector_pub_ = nh.advertise<geometry_msgs::PointStamped>("end_effector/position", 5);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("perception/markers", 2);
    if (config.publish_debug_image) debug_pub_ = image_transport_.advertise("perception/debug_image", 1);
    image_sub_ = image_transport_.subscribe("camera/color/image_raw", 2, &HarvestPerceptionNode::onImage, this);
    cloud_sub_ = nh.subscribe("camera/depth/points", 2, &HarvestPerceptionNode::onCloud, this);
    if (config.use_camera_info)
      info_sub_ = nh.subscribe("camera/color/camera_info", 1, &HarvestPerceptionNode::onCameraInfo, this);
    if (config.arm_prior)
      joints_sub_ = nh.subscribe("manipulator/joint_states", 5, &HarvestPerceptionNode::onJoints, this);

    diagnostics_.setHardwareID("harvest_perception");
    diagnostics_.add("perception", this, &HarvestPerceptionNode::diagnose);
    diagnostics_timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { diagnostics_.update(); });
    ROS_INFO("harvest_perception: %s detector, intrinsics fx %.3f fy %.3f cx %.3f cy %.3f (%dx%d)",
             detectorName(config).c_str(), config.pipeline.intrinsics.fx, config.pipeline.intrinsics.fy,
             config.pipeline.intrinsics.cx, config.pipeline.intrinsics.cy, config.pipeline.intrinsics.width,
             config.pipeline.intrinsics.height);
  }

 private:
  static std::string detectorName(const PerceptionNodeConfig& config) {
    if (config.use_network) return "boll network (" + config.network.model_path + ")";
    return config.use_darknet ? "tiny-YOLOv3 (Darknet)" : "colour/shape";
  }

  static std::unique_ptr<BollDetector> makeDetector(const PerceptionNodeConfig& config) {
    if (config.use_network) return std::make_unique<NetworkBollDetector>(config.network);
    if (config.use_darknet) return std::make_unique<DarknetBollDetector>(config.darknet);
    return std::make_unique<ColourBollDetector>(config.colour);
  }

  void reject(const std::string& reason) {
    ++rejected_[reason];
    ROS_WARN_THROTTLE(5.0, "harvest_perception: frame rejected: %s", reason.c_str());
  }

  void onImage(const sensor_msgs::ImageConstPtr& message) {
    cv_bridge::CvImageConstPtr image;
    try {
      image = cv_bridge::toCvShare(message, sensor_msgs::image_encodings::BGR8);
    } catch (const cv_bridge::Exception& e) {
      return reject(std::string("image conversion: ") + e.what());
    } catch (const cv::Exception& e) {
      return reject(std::string("image conversion: ") + e.what());
    }
    if (image->image.empty()) return reject(toString(FrameStatus::kEmptyImage));
    if (image_) ++unpaired_;
    image_ = image;
    tryProcess();
  }

  void onCloud(const sensor_msgs::PointCloud2ConstPtr& message) {
    cv::Mat points;
    std::string error;
    if (!cloudToMat(*message, &points, &error)) return reject("cloud: " + error);
    if (cloud_) ++unpaired_;
    cloud_ = StampedCloud{message->header.stamp, points};
    tryProcess();
  }

  void onCameraInfo(const sensor_msgs::CameraInfoConstPtr& info) {
    CameraIntrinsics intrinsics;
    intrinsics.fx = info->K[0];
    intrinsics.fy = info->K[4];
    intrinsics.cx = info->K[2];
    intrinsics.cy = info->K[5];
    intrinsics.width = static_cast<int>(info->width);
    intrinsics.height = static_cast<int>(info->height);
    try {
      pipeline_.setIntrinsics(intrinsics);
    } catch (const std::invalid_argument& e) {
      reject(std::string("camera_info: ") + e.what());
    }
  }

  /// The arm's position from its own sensing (stepper counters through the manipulator node's calibration).
  void onJoints(const sensor_msgs::JointStateConstPtr& message) {
    for (std::size_t i = 0; i < message->name.size() && i < message->position.size(); ++i) {
      if (!std::isfinite(message->position[i])) continue;
      if (message->name[i] == "horizontal") arm_extension_m_ = message->position[i];
      if (message->name[i] == "vertical") arm_depth_m_ = message->position[i];
    }
    arm_stamp_ = message->header.stamp;
  }

  /// Where the arm puts the housing's top face at `stamp`, when its joint states are that recent.
  std::optional<EndEffectorPrior> armPrior(const ros::Time& stamp) const {
    if (!config_.arm_prior || !arm_extension_m_ || !arm_depth_m_) return std::nullopt;
    if (std::abs((stamp - arm_stamp_).toSec()) > config_.arm_prior_max_age_s) return std::nullopt;
    EndEffectorPrior prior;
    prior.position = cv::Point3d(*arm_extension_m_ + config_.arm_extension_zero_x_m, 0.0, *arm_depth_m_);
    prior.radius_m = config_.arm_prior_radius_m;
    prior.housing_half_m = config_.arm_housing_half_m;
    return prior;
  }

  void tryProcess() {
    if (!image_ || !cloud_) return;
    const double gap = (image_->header.stamp - cloud_->stamp).toSec();
    if (std::abs(gap) > config_.max_stamp_diff_s) {
      // Keep the newer one and wait for its partner.
      ++unpaired_;
      if (gap > 0.0)
        cloud_.reset();
      else
        image_.reset();
      return;
    }
    const cv_bridge::CvImageConstPtr image = image_;
    const cv::Mat cloud = cloud_->points;
    image_.reset();
    cloud_.reset();

    const ros::WallTime start = ros::WallTime::now();
    const std::optional<EndEffectorPrior> prior = armPrior(image->header.stamp);
    if (config_.arm_prior && !prior) ++frames_without_arm_;
    const FrameResult result =
        prior ? pipeline_.process(image->image, cloud, prior) : pipeline_.process(image->image, cloud);
    const double ms = (ros::WallTime::now() - start).toSec() * 1e3;
    if (result.status != FrameStatus::kOk) return reject(toString(result.status));
    if (result.bolls.empty() && result.bolls_detected > 0) {
      // Publishing "no bolls" would send the rover on along the row past bolls it saw but could not locate.
      bolls_without_depth_ += result.bolls_without_depth;
      return reject("bolls seen but none has depth");
    }

    ++processed_;
    last_ms_ = ms;
    total_ms_ += ms;
    last_bolls_ = static_cast<int>(result.bolls.size());
    bolls_without_depth_ += result.bolls_without_depth;
    end_effector_found_ += result.end_effector.has_value();
    last_processed_ = ros::Time::now();

    const std_msgs::Header& header = image->header;
    bolls_pub_.publish(toBollArray(result, header));
    if (result.end_effector) {
      geometry_msgs::PointStamped point;
      point.header = header;
      point.point.x = result.end_effector->position.x;
      point.point.y = result.end_effector->position.y;
      point.point.z = result.end_effector->position.z;
      end_effector_pub_.publish(point);
    }
    if (markers_pub_.getNumSubscribers() > 0) markers_pub_.publish(toMarkers(result, header));
    if (config_.publish_debug_image && debug_pub_.getNumSubscribers() > 0)
      debug_pub_.publish(cv_bridge::CvImage(header, "bgr8", drawDebugOverlay(image->image, result)).toImageMsg());
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
    int rejected = 0;
    for (const auto& [reason, count] : rejected_) rejected += count;
    if (processed_ == 0) {
      status.summary(diagnostic_msgs::DiagnosticStatus::WARN, rejected ? "every frame rejected" : "no frames yet");
    } else if (rejected > reported_rejected_) {
      status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "frames rejected since last report");
    } else if (end_effector_found_ == 0) {
      status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "end-effector never seen");
    } else {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    }
    reported_rejected_ = rejected;
    status.add("detector", config_.use_network ? "network" : config_.use_darknet ? "darknet" : "colour");
    status.add("frames processed", processed_);
    status.add("frames rejected", rejected);
    for (const auto& [reason, count] : rejected_) status.add("rejected: " + reason, count);
    status.add("unpaired image or cloud", unpaired_);
    status.add("bolls last frame", last_bolls_);
    status.add("bolls without depth", bolls_without_depth_);
    status.add("end-effector found", end_effector_found_);
    if (config_.arm_prior) status.add("frames without the arm's position (whole-image search)", frames_without_arm_);
    status.add("last frame [ms]", last_ms_);
    status.add("mean frame [ms]", processed_ ? total_ms_ / processed_ : 0.0);
    status.add("last frame at", last_processed_.toSec());
  }

  struct StampedCloud {
    ros::Time stamp;
    cv::Mat points;
  };

  PerceptionNodeConfig config_;
  PerceptionPipeline pipeline_;
  image_transport::ImageTransport image_transport_;
  image_transport::Subscriber image_sub_;
  image_transport::Publisher debug_pub_;
  ros::Subscriber cloud_sub_, info_sub_, joints_sub_;
  ros::Publisher bolls_pub_, end_effector_pub_, markers_pub_;
  diagnostic_updater::Updater diagnostics_;
  ros::Timer diagnostics_timer_;

  cv_bridge::CvImageConstPtr image_;
  std::optional<StampedCloud> cloud_;
  std::map<std::string, int> rejected_;
  int reported_rejected_ = 0;
  int processed_ = 0, unpaired_ = 0, last_bolls_ = 0, bolls_without_depth_ = 0, end_effector_found_ = 0;
  double last_ms_ = 0.0, total_ms_ = 0.0;
  ros::Time last_processed_;
  std::optional<double> arm_extension_m_, arm_depth_m_;
  ros::Time arm_stamp_;
  int frames_without_arm_ = 0;
};

}  // namespace cotton_harvester

int main(int argc, char** argv) {
  ros::init(argc, argv, "harvest_perception");
  ros::NodeHandle nh, pnh("~");
  cotton_harvester::PerceptionNodeConfig config;
  std::string error;
  if (!cotton_harvester::loadPerceptionNodeConfig(pnh, &config, &error)) {
    ROS_FATAL("harvest_perception: bad parameters: %s", error.c_str());
    return 1;
  }
  std::unique_ptr<cotton_harvester::HarvestPerceptionNode> node;
  try {
    node = std::make_unique<cotton_harvester::HarvestPerceptionNode>(nh, pnh, config);
  } catch (const std::exception& e) {
    ROS_FATAL("harvest_perception: cannot start: %s", e.what());
    return 1;
  }
  ros::spin();
  return 0;
}
