#include <cmath>

#include <gtest/gtest.h>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/testing/detection_scoring.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/testing/scene_renderer.h"

using namespace cotton_harvester::perception;

namespace {

ScoreSummary runFrames(Lighting lighting, int frames, std::uint32_t first_seed) {
  PerceptionPipeline pipeline(PerceptionParams{}, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  SceneParams scene;
  scene.lighting = lighting;
  ScoreSummary summary;
  for (int i = 0; i < frames; ++i) {
    const SyntheticFrame frame = makeSyntheticFrame(scene, first_seed + i);
    summary.add(scoreFrame(pipeline.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
  }
  return summary;
}

/// The end-effector within 3 cm on average and 8 cm at worst (a leaf over part of it moves its centroid).
void expectEndEffectorErrors(const ScoreSummary& s) {
  ASSERT_FALSE(s.end_effector_errors_m.empty());
  double sum = 0.0;
  for (double e : s.end_effector_errors_m) {
    EXPECT_LT(e, 0.08);
    sum += e;
  }
  EXPECT_LT(sum / s.end_effector_errors_m.size(), 0.03);
}

}  // namespace

TEST(SyntheticScene, IsDeterministicAndItsCloudAgreesWithItsTruth) {
  SceneParams scene;
  scene.depth_noise_per_m2 = 0.0;
  scene.hole_fraction = 0.0;
  scene.hole_blobs = 0;
  scene.invalid_left_columns = 0;
  const SyntheticFrame a = makeSyntheticFrame(scene, 42);
  const SyntheticFrame b = makeSyntheticFrame(scene, 42);
  EXPECT_EQ(cv::norm(a.bgr, b.bgr, cv::NORM_INF), 0.0);
  ASSERT_FALSE(a.layout.bolls.empty());
  ASSERT_TRUE(a.layout.end_effector.has_value());
  const CameraIntrinsics k;
  int checked = 0;
  for (const TrueBoll& boll : a.layout.bolls) {
    // The truth is consistent with itself: pixel = projection of the centre, surface on the ray to the centre.
    const cv::Point2d pixel = project(k, boll.centre);
    EXPECT_NEAR(pixel.x, boll.pixel.x, 1e-9);
    const cv::Point3d d = boll.centre - boll.surface;
    EXPECT_NEAR(std::sqrt(d.dot(d)), boll.radius_m, 1e-9);
    if (boll.visible_fraction < 0.99) continue;
    // A fully visible boll: the cloud at its centre pixel lies on its surface, at the truth's surface point to
    // within the half-pixel offset of the pixel grid.
    const cv::Point p(static_cast<int>(std::lround(boll.pixel.x)), static_cast<int>(std::lround(boll.pixel.y)));
    const cv::Vec3f point = a.cloud.at<cv::Vec3f>(p);
    const cv::Point3d q(point[0], point[1], point[2]);
    const cv::Point3d from_centre = q - boll.centre;
    EXPECT_NEAR(std::sqrt(from_centre.dot(from_centre)), boll.radius_m, 1e-3);
    const cv::Point3d error = q - boll.surface;
    EXPECT_LT(std::sqrt(error.dot(error)), 0.004);
    ++checked;
  }
  EXPECT_GT(checked, 0);
  // The end-effector's top face is orange in the image and at its depth in the cloud.
  const cv::Point ee(static_cast<int>(std::lround(a.layout.end_effector->pixel.x)),
                     static_cast<int>(std::lround(a.layout.end_effector->pixel.y)));
  const cv::Vec3b colour = a.bgr.at<cv::Vec3b>(ee);
  const float ee_depth = a.cloud.at<cv::Vec3f>(ee)[2];
  if (std::abs(ee_depth - a.layout.end_effector->top_centre.z) < 1e-3) {  // not hidden under a leaf
    EXPECT_GE(colour[2], 200);
    EXPECT_LE(colour[0], 60);
  }
}

TEST(SyntheticScene, CloudHasTheRequestedHoles) {
  SceneParams scene;
  const SyntheticFrame frame = makeSyntheticFrame(scene, 7);
  int nan_count = 0;
  for (int v = 0; v < frame.cloud.rows; ++v)
    for (int u = 0; u < frame.cloud.cols; ++u) nan_count += std::isnan(frame.cloud.at<cv::Vec3f>(v, u)[2]);
  const double expected_min = scene.invalid_left_columns * 720 + 0.9 * scene.hole_fraction * 1280 * 720;
  EXPECT_GT(nan_count, expected_min);
  EXPECT_LT(nan_count, expected_min + 0.02 * 1280 * 720);
  EXPECT_TRUE(std::isnan(frame.cloud.at<cv::Vec3f>(100, 5)[0]));  // invalid left border
}

// Tolerances: the colour detector must find at least 85% of the bolls that are at least half visible with at
// least 90% precision, and place them within 2 cm on average (the stereo noise at 1.5 m is 4.5 mm; the
// centroid of a partly shaded or occluded boll moves by a few pixels).
TEST(SyntheticAccuracy, SunnyFrames) {
  const ScoreSummary s = runFrames(Lighting::kSunny, 12, 500);
  EXPECT_GT(s.true_positives, 50);
  EXPECT_GE(s.precision(), 0.90);
  EXPECT_GE(s.recall(), 0.85);
  EXPECT_LE(s.meanError3d(), 0.02);
  EXPECT_GE(s.end_effector_found, s.end_effector_expected - 1);
  expectEndEffectorErrors(s);
}

TEST(SyntheticAccuracy, CloudyFrames) {
  const ScoreSummary s = runFrames(Lighting::kCloudy, 12, 900);
  EXPECT_GT(s.true_positives, 50);
  EXPECT_GE(s.precision(), 0.90);
  EXPECT_GE(s.recall(), 0.85);
  EXPECT_LE(s.meanError3d(), 0.02);
  EXPECT_GE(s.end_effector_found, s.end_effector_expected - 1);
  expectEndEffectorErrors(s);
}

TEST(DetectionScoring, CountsMatchesMissesAndFalseAlarms) {
  SceneLayout truth;
  TrueBoll seen, hidden, missed;
  seen.pixel = {100, 100};
  seen.radius_px = 10;
  seen.surface = {0.1, 0.1, 1.0};
  seen.visible_fraction = 1.0;
  hidden = seen;
  hidden.pixel = {300, 100};
  hidden.visible_fraction = 0.2;
  missed = seen;
  missed.pixel = {500, 100};
  truth.bolls = {seen, hidden, missed};
  FrameResult result;
  LocatedBoll a, b, c;
  a.detection.centroid = {104, 103};  // 5 px from seen
  a.position = {0.1, 0.1, 1.03};
  b.detection.centroid = {300, 102};  // on the hidden boll: neither true nor false positive
  c.detection.centroid = {700, 100};  // nothing there
  result.bolls = {a, b, c};
  const FrameScore score = scoreFrame(result, truth, ScoringParams{});
  EXPECT_EQ(score.true_positives, 1);
  EXPECT_EQ(score.matched_hidden, 1);
  EXPECT_EQ(score.false_positives, 1);
  EXPECT_EQ(score.false_negatives, 1);
  ASSERT_EQ(score.errors_3d_m.size(), 1u);
  EXPECT_NEAR(score.errors_3d_m[0], 0.03, 1e-9);
  ScoreSummary summary;
  summary.add(score);
  EXPECT_DOUBLE_EQ(summary.precision(), 0.5);
  EXPECT_DOUBLE_EQ(summary.recall(), 0.5);
}
