// Starts harvest_perception as a user would (rosrun with private parameters) in configurations the launch file
// does not use, and checks what it publishes.

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cv_bridge/cv_bridge.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/perception/camera_model.h"
#include "cotton_harvester/testing/darknet_net_writer.h"
#include "node_test_helpers.h"

using namespace cotton_harvester;
using namespace cotton_harvester::perception;
using cotton_harvester::test::toCloud;
using cotton_harvester::test::waitFor;

namespace {

/// A harvest_perception process started with rosrun; stopped (SIGINT) and reaped when destroyed.
class NodeProcess {
 public:
  explicit NodeProcess(const std::vector<std::string>& arguments) {
    pid_ = ::fork();
    if (pid_ != 0) return;
    // The default stop handling, whatever the test suite inherited (started in the background, it ignores SIGINT).
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    std::vector<std::string> all = {"rosrun", "cotton_harvester", "harvest_perception"};
    all.insert(all.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execvp("rosrun", argv.data());
    ::_exit(127);
  }
  ~NodeProcess() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGINT);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  bool started() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

/// Organised cloud of a plane at depth z for the given intrinsics.
cv::Mat planeCloud(const CameraIntrinsics& k, double z) {
  cv::Mat points(k.height, k.width, CV_32FC3);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u)
      points.at<cv::Vec3f>(v, u) = {float((u - k.cx) / k.fx * z), float((v - k.cy) / k.fy * z), float(z)};
  return points;
}

/// Puts a boll into a cloud: a sphere whose point nearest the lens lies on the ray through pixel `centre` at depth
/// z, its radius the disc's (radius_px) at that distance; each pixel whose ray meets it takes that point.
void addSphere(cv::Mat* points, const CameraIntrinsics& k, const cv::Point& centre, int radius_px, double z) {
  const auto ray = [&k](double u, double v) {
    const cv::Vec3d r((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
    return r / cv::norm(r);
  };
  const cv::Vec3d axis = ray(centre.x, centre.y);
  const double apex = z / axis[2], radius = apex * radius_px / k.fx;
  const cv::Vec3d c = axis * (apex + radius);
  for (int v = centre.y - radius_px - 2; v <= centre.y + radius_px + 2; ++v)
    for (int u = centre.x - radius_px - 2; u <= centre.x + radius_px + 2; ++u) {
      const cv::Vec3d r = ray(u, v);
      const double b = r.dot(c), disc = b * b - (c.dot(c) - radius * radius);
      if (disc < 0.0) continue;
      const cv::Vec3d p = r * (b - std::sqrt(disc));
      points->at<cv::Vec3f>(v, u) = cv::Vec3f(float(p[0]), float(p[1]), float(p[2]));
    }
}

/// A 128x128 network with a known answer: a detection at the centre of every 32-pixel cell (of the input) whose
/// brightest pixel is white, box 32x32 input pixels, confidence sigmoid(2) x sigmoid(1) = 0.64.
DarknetNet knownNet() {
  DarknetNet net;
  net.width = net.height = 128;
  net.sections.push_back(
      {"convolutional", {{"filters", "1"}, {"size", "1"}, {"stride", "1"}, {"activation", "linear"}}});
  ConvolutionWeights grey;
  grey.biases = {0.0f};
  grey.weights = {1.0f / 3, 1.0f / 3, 1.0f / 3};
  net.convolutions.push_back(grey);
  for (int i = 0; i < 5; ++i) net.sections.push_back({"maxpool", {{"size", "2"}, {"stride", "2"}}});
  net.sections.push_back(
      {"convolutional", {{"filters", "6"}, {"size", "1"}, {"stride", "1"}, {"activation", "linear"}}});
  ConvolutionWeights head;
  head.biases = {0.0f, 0.0f, 0.0f, 0.0f, -18.0f, 1.0f};
  head.weights = {0.0f, 0.0f, 0.0f, 0.0f, 20.0f, 0.0f};
  net.convolutions.push_back(head);
  net.sections.push_back({"yolo", {{"mask", "0"}, {"anchors", "32,32"}, {"classes", "1"}, {"num", "1"}}});
  return net;
}

/// Publishers and the bolls subscriber of one node's namespace.
struct NodeTopics {
  explicit NodeTopics(const std::string& ns) : nh(ns) {
    image = nh.advertise<sensor_msgs::Image>("camera/color/image_raw", 2);
    cloud = nh.advertise<sensor_msgs::PointCloud2>("camera/depth/points", 2);
    info = nh.advertise<sensor_msgs::CameraInfo>("camera/color/camera_info", 2, true);
    bolls = nh.subscribe<BollArray>("bolls", 2, [this](const BollArray::ConstPtr& m) { received.push_back(*m); });
  }
  bool connected(bool with_info) const {
    return image.getNumSubscribers() > 0 && cloud.getNumSubscribers() > 0 && bolls.getNumPublishers() > 0 &&
           (!with_info || info.getNumSubscribers() > 0);
  }
  void send(const cv::Mat& bgr, const cv::Mat& points, double stamp) {
    std_msgs::Header h;
    h.stamp = ros::Time(stamp);
    h.frame_id = "camera_left_optical";
    cloud.publish(toCloud(points, h));
    image.publish(cv_bridge::CvImage(h, "bgr8", bgr).toImageMsg());
  }

  ros::NodeHandle nh;
  ros::Publisher image, cloud, info;
  ros::Subscriber bolls;
  std::vector<BollArray> received;
};

}  // namespace

TEST(HarvestPerceptionVariants, DarknetNodeLoadsTheConfiguredNetworkAndPublishesItsDetections) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("cotton_harvester_node_net_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string cfg = (dir / "known.cfg").string(), weights = (dir / "known.weights").string();
  writeDarknetFiles(knownNet(), cfg, weights);

  NodeTopics topics("dnn");
  {
    NodeProcess node({"__name:=dnn_perception", "__ns:=dnn", "_darknet/cfg:=" + cfg, "_darknet/weights:=" + weights,
                      "_darknet/input_width:=128", "_darknet/input_height:=128",
                      // a flat cloud has no ground below the detections and the known net's boxes are cells
                      "_check_plausibility:=false"});
    ASSERT_TRUE(node.started());
    ASSERT_TRUE(waitFor([&] { return topics.connected(false); }, 30.0)) << "the DNN node did not come up";
    // 1280x720 to 128x128: a cell is 320 x 180 image pixels. White blocks in cells (row 1, col 2) and (3, 0).
    cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(0, 0, 0));
    cv::rectangle(image, cv::Rect(750, 240, 100, 60), cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(image, cv::Rect(110, 600, 100, 60), cv::Scalar(255, 255, 255), cv::FILLED);
    topics.send(image, planeCloud(CameraIntrinsics{}, 1.5), 2000.0);
    ASSERT_TRUE(waitFor([&] { return !topics.received.empty(); }, 30.0)) << "the DNN node published no bolls";
  }
  std::filesystem::remove_all(dir);

  const BollArray& message = topics.received.front();
  ASSERT_EQ(message.bolls.size(), 2u);
  std::set<std::pair<int, int>> centres;
  for (const Boll& b : message.bolls) {
    centres.insert({b.u, b.v});
    EXPECT_NEAR(b.confidence, 1.0 / (1.0 + std::exp(-2.0)) / (1.0 + std::exp(-1.0)), 1e-3);
    EXPECT_NEAR(b.position.z, 1.5, 1e-3);
  }
  EXPECT_EQ(centres, (std::set<std::pair<int, int>>{{800, 270}, {160, 630}}));
}

TEST(HarvestPerceptionVariants, CameraInfoReplacesTheIntrinsics) {
  // A 640x360 camera: with the 720p defaults every frame would be rejected as the wrong size.
  CameraIntrinsics half;
  half.fx = half.fy = 350.0;
  half.cx = 320.0;
  half.cy = 180.0;
  half.width = 640;
  half.height = 360;
  NodeTopics topics("info");
  // A flat cloud has no ground below the boll.
  NodeProcess node({"__name:=info_perception", "__ns:=info", "_use_camera_info:=true", "_check_plausibility:=false"});
  ASSERT_TRUE(node.started());
  ASSERT_TRUE(waitFor([&] { return topics.connected(true); }, 30.0)) << "the node did not come up";
  sensor_msgs::CameraInfo info;
  info.width = 640;
  info.height = 360;
  info.K = {350.0, 0.0, 320.0, 0.0, 350.0, 180.0, 0.0, 0.0, 1.0};
  topics.info.publish(info);

  // One boll 100 px right of the centre at 1.4 m: x = 100 * 1.4 / 350 = 0.4 m with the camera_info focal length.
  cv::Mat image(360, 640, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {420, 180}, 12, cv::Scalar(235, 238, 240), cv::FILLED);
  cv::Mat points = planeCloud(half, 2.0);
  addSphere(&points, half, {420, 180}, 12, 1.4);
  // The info is latched but may arrive after the first frames: send until a frame is accepted.
  double stamp = 3000.0;
  const bool got = waitFor(
      [&] {
        if (!topics.received.empty()) return true;
        topics.send(image, points, stamp += 1.0);
        return false;
      },
      30.0);
  ASSERT_TRUE(got) << "no frame was accepted with the camera_info intrinsics";
  ASSERT_EQ(topics.received.front().bolls.size(), 1u);
  const Boll& boll = topics.received.front().bolls[0];
  EXPECT_NEAR(boll.position.x, 100.0 * 1.4 / 350.0, 2e-3);
  EXPECT_NEAR(boll.position.z, 1.4, 2e-3);
  EXPECT_EQ(boll.u, 420);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_harvest_perception_variants");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
