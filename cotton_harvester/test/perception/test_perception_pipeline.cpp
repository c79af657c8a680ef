#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"

using namespace cotton_harvester::perception;

namespace {

struct Disc {
  cv::Point centre;
  int radius_px;
  double z;
};

/// A hand-made frame: soil at 2.2 m, white discs (bolls) and an orange block (end-effector) at given depths.
class HandMadeFrame {
 public:
  HandMadeFrame() : image(720, 1280, CV_8UC3, cv::Scalar(60, 100, 140)), depth(720, 1280, CV_64F, cv::Scalar(2.2)) {}

  void addBoll(const Disc& d) {
    cv::circle(image, d.centre, d.radius_px, cv::Scalar(235, 238, 240), cv::FILLED);
    cv::circle(depth, d.centre, d.radius_px, cv::Scalar(d.z), cv::FILLED);
  }
  void addEndEffector(const cv::Rect& r, double z) {
    cv::rectangle(image, r, cv::Scalar(10, 120, 245), cv::FILLED);
    cv::rectangle(depth, r, cv::Scalar(z), cv::FILLED);
  }
  cv::Mat cloud() const {
    const CameraIntrinsics k;
    cv::Mat points(720, 1280, CV_32FC3);
    for (int v = 0; v < 720; ++v)
      for (int u = 0; u < 1280; ++u) {
        const double z = depth.at<double>(v, u);
        points.at<cv::Vec3f>(v, u) = {float((u - k.cx) / k.fx * z), float((v - k.cy) / k.fy * z), float(z)};
      }
    return points;
  }

  cv::Mat image;
  cv::Mat depth;
};

PerceptionPipeline makePipeline(NearestBy nearest_by = NearestBy::kCamera) {
  PerceptionParams params;
  params.nearest_by = nearest_by;
  return PerceptionPipeline(params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
}

HandMadeFrame threeBolls() {
  HandMadeFrame frame;
  frame.addBoll({{400, 300}, 16, 1.2});   // x = -0.49 m: reachable, closest to the lens
  frame.addBoll({{1200, 300}, 16, 1.3});  // x = +0.96 m: beyond the 0.70 m horizontal arm
  frame.addBoll({{700, 500}, 14, 1.6});   // reachable, next to the end-effector
  frame.addEndEffector({660, 520, 60, 40}, 1.55);
  return frame;
}

}  // namespace

TEST(PerceptionPipeline, LocatesBollsEndEffectorAndTheNearestReachable) {
  const HandMadeFrame frame = threeBolls();
  PerceptionPipeline pipeline = makePipeline();
  const FrameResult result = pipeline.process(frame.image, frame.cloud());
  ASSERT_EQ(result.status, FrameStatus::kOk);
  ASSERT_EQ(result.bolls.size(), 3u);
  EXPECT_EQ(result.bolls_without_depth, 0);
  const CameraIntrinsics k;
  int reachable = 0;
  for (const LocatedBoll& boll : result.bolls) {
    const double u = boll.detection.centroid.x, v = boll.detection.centroid.y;
    const double z = boll.position.z;
    EXPECT_NEAR(boll.position.x, (u - k.cx) / k.fx * z, 1e-3);
    EXPECT_NEAR(boll.position.y, (v - k.cy) / k.fy * z, 1e-3);
    if (std::abs(u - 400) < 2) {
      EXPECT_NEAR(z, 1.2, 1e-3);
    }
    if (std::abs(u - 1200) < 2) {
      EXPECT_NEAR(z, 1.3, 1e-3);
      EXPECT_FALSE(boll.reachable);
    }
    reachable += boll.reachable;
  }
  EXPECT_EQ(reachable, 2);
  ASSERT_GE(result.nearest_reachable, 0);
  EXPECT_NEAR(result.bolls[result.nearest_reachable].detection.centroid.x, 400.0, 1.0);

  ASSERT_TRUE(result.end_effector.has_value());
  EXPECT_NEAR(result.end_effector->position.z, 1.55, 1e-3);
  EXPECT_NEAR(result.end_effector->position.x, (689.5 - k.cx) / k.fx * 1.55, 2e-3);
}

TEST(PerceptionPipeline, NearestToTheEndEffectorWhenAsked) {
  const HandMadeFrame frame = threeBolls();
  PerceptionPipeline pipeline = makePipeline(NearestBy::kEndEffector);
  const FrameResult result = pipeline.process(frame.image, frame.cloud());
  ASSERT_GE(result.nearest_reachable, 0);
  EXPECT_NEAR(result.bolls[result.nearest_reachable].detection.centroid.x, 700.0, 1.0);
}

TEST(PerceptionPipeline, TheEndEffectorIsNotABoll) {
  HandMadeFrame frame;
  frame.addEndEffector({600, 300, 60, 40}, 1.5);
  cv::rectangle(frame.image, cv::Rect(615, 310, 30, 20), cv::Scalar(240, 240, 240), cv::FILLED);  // white label
  PerceptionPipeline pipeline = makePipeline();
  const FrameResult result = pipeline.process(frame.image, frame.cloud());
  EXPECT_EQ(result.bolls_detected, 0);
  EXPECT_EQ(result.nearest_reachable, -1);
}

TEST(PerceptionPipeline, BadInputIsRejectedWithAReason) {
  const HandMadeFrame frame = threeBolls();
  PerceptionPipeline pipeline = makePipeline();
  EXPECT_EQ(pipeline.process(cv::Mat(), frame.cloud()).status, FrameStatus::kEmptyImage);
  cv::Mat grey;
  cv::cvtColor(frame.image, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(pipeline.process(grey, frame.cloud()).status, FrameStatus::kBadImage);
  cv::Mat small;
  cv::resize(frame.image, small, {640, 360});
  EXPECT_EQ(pipeline.process(small, cv::Mat()).status, FrameStatus::kSizeMismatch);

  // No depth at all: the bolls are seen but cannot be placed.
  const FrameResult no_cloud = pipeline.process(frame.image, cv::Mat());
  EXPECT_EQ(no_cloud.status, FrameStatus::kNoDepth);
  EXPECT_EQ(no_cloud.bolls_detected, 3);
  EXPECT_EQ(no_cloud.bolls_without_depth, 3);
  EXPECT_TRUE(no_cloud.bolls.empty());
  EXPECT_EQ(pipeline.process(frame.image, cv::Mat(360, 640, CV_32FC3)).status, FrameStatus::kNoDepth);

  // A cloud of NaN: same, and the end-effector is seen but not located.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const cv::Mat nan_cloud(720, 1280, CV_32FC3, cv::Scalar(nan, nan, nan));
  const FrameResult all_nan = pipeline.process(frame.image, nan_cloud);
  EXPECT_EQ(all_nan.status, FrameStatus::kOk);
  EXPECT_TRUE(all_nan.bolls.empty());
  EXPECT_EQ(all_nan.bolls_without_depth, 3);
  EXPECT_EQ(all_nan.nearest_reachable, -1);
  EXPECT_TRUE(all_nan.end_effector_image.has_value());
  EXPECT_FALSE(all_nan.end_effector.has_value());

  // NaN over one boll only: the other two are still located.
  cv::Mat holed = frame.cloud();
  cv::circle(holed, {400, 300}, 20, cv::Scalar(nan, nan, nan), cv::FILLED);
  const FrameResult partial = pipeline.process(frame.image, holed);
  EXPECT_EQ(partial.bolls.size(), 2u);
  EXPECT_EQ(partial.bolls_without_depth, 1);
  ASSERT_GE(partial.nearest_reachable, 0);
  EXPECT_NEAR(partial.bolls[partial.nearest_reachable].detection.centroid.x, 700.0, 1.0);
}

TEST(PerceptionPipeline, RejectsBadParametersAndIntrinsics) {
  PerceptionParams params;
  params.reach.horizontal_arm_length_m = -0.1;
  EXPECT_THROW(PerceptionPipeline(params, std::make_unique<ColourBollDetector>(ColourBollParams{})),
               std::invalid_argument);
  EXPECT_THROW(PerceptionPipeline(PerceptionParams{}, nullptr), std::invalid_argument);
  PerceptionPipeline pipeline = makePipeline();
  CameraIntrinsics bad;
  bad.fy = -1.0;
  EXPECT_THROW(pipeline.setIntrinsics(bad), std::invalid_argument);
  CameraIntrinsics half;
  half.width = 640;
  half.height = 360;
  pipeline.setIntrinsics(half);
  EXPECT_EQ(pipeline.params().intrinsics.width, 640);
}
