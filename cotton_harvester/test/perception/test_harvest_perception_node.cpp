// Drives harvest_perception with synthetic frames and checks what it publishes against the frames' truth, and
// that bad input is rejected, reported in diagnostics, and does not stop the node.

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>

#include <sys/wait.h>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PointStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <thorvald_common/ros/wait_for.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/testing/detection_scoring.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/testing/scene_renderer.h"
#include "node_test_helpers.h"

using namespace cotton_harvester;
using namespace cotton_harvester::perception;
using cotton_harvester::test::toCloud;

namespace {

class HarvestPerceptionNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    image_pub_ = nh_.advertise<sensor_msgs::Image>("camera/color/image_raw", 2);
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("camera/depth/points", 2);
    bolls_sub_ = nh_.subscribe<BollArray>("bolls", 10, [this](const BollArray::ConstPtr& m) { bolls_.push_back(*m); });
    ee_sub_ = nh_.subscribe<geometry_msgs::PointStamped>(
        "end_effector/position", 10, [this](const geometry_msgs::PointStamped::ConstPtr& m) { ee_.push_back(*m); });
    debug_sub_ = nh_.subscribe<sensor_msgs::Image>("perception/debug_image", 2,
                                                   [this](const sensor_msgs::Image::ConstPtr& m) { debug_ = *m; });
    diag_sub_ = nh_.subscribe<diagnostic_msgs::DiagnosticArray>(
        "/diagnostics", 10, [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          for (const auto& status : m->status)
            if (status.name.find("perception") != std::string::npos) diag_ = status;
        });
    ASSERT_TRUE(waitFor([this] {
      return image_pub_.getNumSubscribers() > 0 && cloud_pub_.getNumSubscribers() > 0 &&
             bolls_sub_.getNumPublishers() > 0 && debug_sub_.getNumPublishers() > 0;
    })) << "harvest_perception did not come up";
  }

  /// Spins until the condition holds or the deadline [s] passes.
  bool waitFor(const std::function<bool()>& condition, double timeout_s = 20.0) {
    return thorvald_common::waitFor(condition, timeout_s);
  }

  std_msgs::Header header(int sequence) {
    std_msgs::Header h;
    h.frame_id = "camera_left_optical";
    h.stamp = ros::Time(1000.0 + sequence);
    return h;
  }

  void send(const cv::Mat& bgr, const cv::Mat& points, const std_msgs::Header& h) {
    cloud_pub_.publish(toCloud(points, h));
    image_pub_.publish(cv_bridge::CvImage(h, "bgr8", bgr).toImageMsg());
  }

  const BollArray* bollsAt(const ros::Time& stamp) const {
    for (const BollArray& b : bolls_)
      if (b.header.stamp == stamp) return &b;
    return nullptr;
  }

  double diagnosticValue(const std::string& key) const {
    for (const auto& kv : diag_.values)
      if (kv.key == key) return std::stod(kv.value);
    return -1.0;
  }

  ros::NodeHandle nh_;
  ros::Publisher image_pub_, cloud_pub_;
  ros::Subscriber bolls_sub_, ee_sub_, debug_sub_, diag_sub_;
  std::vector<BollArray> bolls_;
  std::vector<geometry_msgs::PointStamped> ee_;
  sensor_msgs::Image debug_;
  diagnostic_msgs::DiagnosticStatus diag_;
};

}  // namespace

TEST_F(HarvestPerceptionNodeTest, PublishesTheBollsAndEndEffectorOfASyntheticFrame) {
  SceneParams scene;
  const SyntheticFrame frame = makeSyntheticFrame(scene, 2024);
  const std_msgs::Header h = header(1);
  send(frame.bgr, frame.cloud, h);
  ASSERT_TRUE(waitFor([&] { return bollsAt(h.stamp) != nullptr && !ee_.empty() && debug_.height > 0; }));
  const BollArray& message = *bollsAt(h.stamp);
  EXPECT_EQ(message.header.frame_id, "camera_left_optical");

  // Against the truth: every published boll lies on a true boll's surface point within 3 cm, and most true
  // bolls that are mostly visible were published.
  FrameResult published;
  for (const Boll& b : message.bolls) {
    LocatedBoll located;
    located.detection.centroid = {double(b.u), double(b.v)};
    located.position = {b.position.x, b.position.y, b.position.z};
    published.bolls.push_back(located);
    EXPECT_GE(b.confidence, 0.0f);
    EXPECT_LE(b.confidence, 1.0f);
    const bool reachable = b.position.z > 0.0 && b.position.z < 1.93 && std::abs(b.position.x) <= 0.70;
    EXPECT_EQ(b.reachable, reachable);
  }
  const FrameScore score = scoreFrame(published, frame.layout, ScoringParams{});
  EXPECT_GE(score.true_positives, 0.8 * (score.true_positives + score.false_positives));
  EXPECT_GE(score.true_positives, 0.8 * (score.true_positives + score.false_negatives));
  for (double e : score.errors_3d_m) EXPECT_LT(e, 0.03);

  // The node is the library with the launch file's parameters (the paper's defaults): same bolls, same order.
  PerceptionPipeline library(PerceptionParams{}, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  const FrameResult expected_result = library.process(frame.bgr, frame.cloud);
  ASSERT_EQ(message.bolls.size(), expected_result.bolls.size());
  for (size_t i = 0; i < message.bolls.size(); ++i) {
    EXPECT_NEAR(message.bolls[i].position.x, expected_result.bolls[i].position.x, 1e-9);
    EXPECT_NEAR(message.bolls[i].position.z, expected_result.bolls[i].position.z, 1e-9);
    EXPECT_EQ(message.bolls[i].reachable, expected_result.bolls[i].reachable);
  }
  EXPECT_EQ(message.nearest_reachable, expected_result.nearest_reachable);

  // The nearest reachable boll is the reachable one with the smallest range.
  double best = std::numeric_limits<double>::infinity();
  int expected = -1;
  for (size_t i = 0; i < message.bolls.size(); ++i) {
    const auto& p = message.bolls[i].position;
    const double r = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    if (message.bolls[i].reachable && r < best) {
      best = r;
      expected = static_cast<int>(i);
    }
  }
  EXPECT_EQ(message.nearest_reachable, expected);

  ASSERT_TRUE(frame.layout.end_effector.has_value());
  const cv::Point3d ee(ee_.back().point.x, ee_.back().point.y, ee_.back().point.z);
  const cv::Point3d ee_error = ee - frame.layout.end_effector->top_centre;
  EXPECT_LT(std::sqrt(ee_error.dot(ee_error)), 0.05);
  EXPECT_EQ(ee_.back().header.stamp, h.stamp);
  EXPECT_EQ(debug_.width, 1280u);
  EXPECT_EQ(debug_.height, 720u);
}

TEST_F(HarvestPerceptionNodeTest, RejectsBadInputReportsItAndKeepsRunning) {
  SceneParams scene;
  scene.lighting = Lighting::kCloudy;
  const SyntheticFrame frame = makeSyntheticFrame(scene, 77);

  // Empty image.
  const std_msgs::Header empty_header = header(10);
  cloud_pub_.publish(toCloud(frame.cloud, empty_header));
  image_pub_.publish(cv_bridge::CvImage(empty_header, "bgr8", cv::Mat()).toImageMsg());
  // A cloud without any depth (all NaN).
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std_msgs::Header nan_header = header(11);
  send(frame.bgr, cv::Mat(frame.cloud.size(), CV_32FC3, cv::Scalar(nan, nan, nan)), nan_header);
  // An unorganised cloud.
  const std_msgs::Header flat_header = header(12);
  cloud_pub_.publish(toCloud(frame.cloud.reshape(3, 1), flat_header));

  ASSERT_TRUE(waitFor([&] { return diagnosticValue("frames rejected") >= 3.0; }))
      << "diagnostics did not report the three rejected inputs";
  EXPECT_EQ(bollsAt(empty_header.stamp), nullptr);
  EXPECT_EQ(bollsAt(nan_header.stamp), nullptr);  // "no bolls" would send the rover past them
  EXPECT_GT(diagnosticValue("bolls without depth"), 0.0);

  // Still alive: a good frame is processed.
  const std_msgs::Header good = header(13);
  send(frame.bgr, frame.cloud, good);
  ASSERT_TRUE(waitFor([&] { return bollsAt(good.stamp) != nullptr; }));
  EXPECT_FALSE(bollsAt(good.stamp)->bolls.empty());
}

TEST(HarvestPerceptionNodeStartup, RefusesBadParametersAndMissingModelsWithANonZeroExit) {
  // Each run gets its own node name, so the running node is untouched; the exit code is the answer (124: the
  // node was still running after 20 s, i.e. it accepted the parameters).
  const auto run = [](const std::string& arguments) {
    const std::string command =
        "timeout 20 rosrun cotton_harvester harvest_perception " + arguments + " > /dev/null 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(run("__name:=bad_window _depth/window_px:=4"), 1);
  EXPECT_EQ(run("__name:=bad_model _depth/model:=stereo"), 1);
  EXPECT_EQ(run("__name:=bad_threshold _end_effector/b_min:=99"), 1);
  EXPECT_EQ(run("__name:=missing_net _darknet/cfg:=/nonexistent/boll.cfg _darknet/weights:=/nonexistent/boll.weights"),
            1);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_harvest_perception_node");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
