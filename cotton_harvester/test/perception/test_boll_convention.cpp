// The 3D convention of a located boll (visible surface point and centre), the size fallback, and the held-out
// bench's split of the 3D error.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "../../bench/perception_bench_gap.h"
#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/testing/heldout_frames.h"

using namespace cotton_harvester::perception;

namespace {

double distance(const cv::Point3d& a, const cv::Point3d& b) {
  const cv::Point3d d = a - b;
  return std::sqrt(d.dot(d));
}

/// Soil 2.2 m below the camera and one white sphere of `radius` at `centre` (camera frame [m]): the colour image
/// shows the sphere's silhouette, the exact cloud the depth where each pixel's ray meets the sphere or the soil.
struct SphereFrame {
  cv::Mat bgr, cloud;
  SphereFrame(const cv::Point3d& centre, double radius) {
    const CameraIntrinsics k;
    bgr = cv::Mat(k.height, k.width, CV_8UC3, cv::Scalar(60, 100, 140));
    cloud = cv::Mat(k.height, k.width, CV_32FC3);
    const cv::Vec3d c(centre.x, centre.y, centre.z);
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u) {
        const cv::Vec3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
        const cv::Vec3d unit = ray / cv::norm(ray);
        const double b = unit.dot(c), disc = b * b - (c.dot(c) - radius * radius);
        cv::Vec3d point = ray * 2.2;
        if (disc >= 0.0) {
          point = unit * (b - std::sqrt(disc));
          bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(235, 238, 240);
        }
        cloud.at<cv::Vec3f>(v, u) = cv::Vec3f(point);
      }
  }
};

cv::Point3d surfaceOf(const cv::Point3d& centre, double radius) {
  return centre * (1.0 - radius / std::sqrt(centre.dot(centre)));
}

}  // namespace

TEST(BollConvention, PositionIsTheVisibleSurfaceAndCentreIsOneRadiusBehind) {
  const double radius = 0.035;
  for (const cv::Point3d& centre : {cv::Point3d(0.0, 0.0, 1.4), cv::Point3d(0.25, -0.12, 1.6)}) {
    const SphereFrame frame(centre, radius);
    PerceptionPipeline pipeline(PerceptionParams{}, std::make_unique<ColourBollDetector>(ColourBollParams{}));
    const FrameResult result = pipeline.process(frame.bgr, frame.cloud);
    ASSERT_EQ(result.bolls.size(), 1u);
    const LocatedBoll& boll = result.bolls[0];
    EXPECT_EQ(boll.depth_source, BollDepthSource::kSurface);
    // The surface point: within 3 mm; the centre: within 3 mm plus the radius estimate's error.
    EXPECT_LT(distance(boll.position, surfaceOf(centre, radius)), 0.003);
    EXPECT_GT(distance(boll.position, centre), radius - 0.003) << "position must not be the centre";
    EXPECT_NEAR(boll.radius_m, radius, 0.004);
    EXPECT_LT(distance(boll.centre, centre), 0.006);
    EXPECT_NEAR(distance(boll.centre, boll.position), boll.radius_m, 1e-9);
  }
  // A boll lower than it is wide (boll_top_fraction): its centre that share of the radius behind the surface.
  PerceptionParams lobed;
  lobed.boll_top_fraction = 0.6;
  const SphereFrame frame(cv::Point3d(0.0, 0.0, 1.4), radius);
  PerceptionPipeline pipeline(lobed, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  const FrameResult result = pipeline.process(frame.bgr, frame.cloud);
  ASSERT_EQ(result.bolls.size(), 1u);
  EXPECT_NEAR(distance(result.bolls[0].centre, result.bolls[0].position), 0.6 * result.bolls[0].radius_m, 1e-9);
}

/// A box detector (as the boll network): one box, the sphere's projected square.
class OneBox : public BollDetector {
 public:
  explicit OneBox(const cv::Rect2d& box) : box_(box) {}
  std::vector<BollDetection> detect(const cv::Mat&, const cv::Mat&) override {
    BollDetection d;
    d.box = box_;
    d.centroid = (box_.tl() + box_.br()) * 0.5;
    d.confidence = 0.9;
    return {d};
  }

 private:
  cv::Rect2d box_;
};

TEST(BollConvention, BoxWithoutDepthAtItsCentreIsLocatedFromItsDisc) {
  const cv::Point3d centre(0.05, 0.02, 1.5);
  const double radius = 0.035;
  SphereFrame frame(centre, radius);
  const CameraIntrinsics k;
  const cv::Point2d pixel = project(k, centre);
  const double r_px = k.fx * radius / std::sqrt(centre.dot(centre));
  // The lint face at the centre gives the stereo matcher nothing: no depth within 0.4 of the radius.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::circle(frame.cloud, cv::Point(static_cast<int>(pixel.x), static_cast<int>(pixel.y)), static_cast<int>(0.4 * r_px),
             cv::Scalar::all(nan), cv::FILLED);
  const cv::Rect2d box(pixel.x - r_px, pixel.y - r_px, 2 * r_px, 2 * r_px);
  PerceptionPipeline pipeline(PerceptionParams{}, std::make_unique<OneBox>(box));
  const FrameResult result = pipeline.process(frame.bgr, frame.cloud);
  ASSERT_EQ(result.bolls.size(), 1u);
  EXPECT_EQ(result.bolls[0].depth_source, BollDepthSource::kSurface);
  EXPECT_LT(distance(result.bolls[0].position, surfaceOf(centre, radius)), 0.005);
  EXPECT_LT(distance(result.bolls[0].centre, centre), 0.008);
}

TEST(BollConvention, CentreBehindSurfaceGoesAlongTheRay) {
  const cv::Point3d surface(0.3, 0.4, 1.2);
  const cv::Point3d centre = centreBehindSurface(surface, 0.04);
  EXPECT_NEAR(distance(centre, surface), 0.04, 1e-12);
  EXPECT_NEAR(centre.x / centre.z, surface.x / surface.z, 1e-12);
  EXPECT_NEAR(centre.y / centre.z, surface.y / surface.z, 1e-12);
}

TEST(SizeFallback, NoDepthGivesThePointFromTheImageSizeWithinItsStatedError) {
  for (const double radius : {0.03, 0.035, 0.042}) {
    const cv::Point3d centre(0.1, 0.05, 1.5);
    SphereFrame frame(centre, radius);
    frame.cloud.setTo(cv::Scalar::all(std::numeric_limits<float>::quiet_NaN()));
    PerceptionParams params;
    params.size_fallback = true;
    PerceptionPipeline pipeline(params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
    const FrameResult result = pipeline.process(frame.bgr, frame.cloud);
    ASSERT_EQ(result.bolls.size(), 1u) << radius;
    EXPECT_EQ(result.bolls_size_fallback, 1);
    EXPECT_EQ(result.bolls_without_depth, 0);
    const LocatedBoll& boll = result.bolls[0];
    EXPECT_EQ(boll.depth_source, BollDepthSource::kImageSize);
    EXPECT_EQ(boll.valid_points, 0);
    // Stated error: the range is off by the ratio of the typical radius to the true one (plus the disc's pixels).
    const double typical = params.geometry.boll_radius_typical_m;
    const double stated = std::abs(typical / radius - 1.0) * std::sqrt(centre.dot(centre)) + 0.02;
    EXPECT_LT(distance(boll.centre, centre), stated) << radius;
    EXPECT_NEAR(distance(boll.centre, boll.position), typical, 1e-9);
  }
  // Without the fallback the boll is dropped as before.
  SphereFrame frame(cv::Point3d(0.1, 0.05, 1.5), 0.035);
  frame.cloud.setTo(cv::Scalar::all(std::numeric_limits<float>::quiet_NaN()));
  PerceptionPipeline off(PerceptionParams{}, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  const FrameResult result = off.process(frame.bgr, frame.cloud);
  EXPECT_TRUE(result.bolls.empty());
  EXPECT_EQ(result.bolls_without_depth, 1);
  ASSERT_EQ(result.dropped.size(), 1u);
  EXPECT_TRUE(result.dropped[0].no_depth);
}

TEST(SizeFallback, RangeIsClampedToWhereBollsGrow) {
  BollDetection tiny;
  tiny.centroid = tiny.centre = cv::Point2d(640.0, 360.0);
  tiny.radius_px = 1.0;  // as far as 24 m for a typical boll
  const BollGeometry g;
  const std::optional<LocatedBoll> boll = locateBySize(tiny, CameraIntrinsics{}, g, 2.2, DepthModel::kRay);
  ASSERT_TRUE(boll);
  EXPECT_LE(boll->centre.z, 2.2 - g.boll_height_min_m + 1e-9);
  BollDetection none;
  EXPECT_FALSE(locateBySize(none, CameraIntrinsics{}, g, 2.2, DepthModel::kRay));
}

TEST(GapScoring, SplitsTheErrorAlongAndAcrossTheRay) {
  double along = 0.0, across = 0.0;
  splitAlongRay(cv::Point3d(0.0, 0.0, 0.02), cv::Point3d(0.0, 0.0, 1.5), &along, &across);
  EXPECT_NEAR(along, 0.02, 1e-12);
  EXPECT_NEAR(across, 0.0, 1e-12);
  splitAlongRay(cv::Point3d(0.01, 0.0, -0.01), cv::Point3d(0.0, 0.0, 1.5), &along, &across);
  EXPECT_NEAR(along, -0.01, 1e-12);
  EXPECT_NEAR(across, 0.01, 1e-12);
  // Off the axis: the ray through the truth, not the optical axis.
  const cv::Point3d truth(1.0, 0.0, 1.0);
  splitAlongRay(truth * (0.03 / std::sqrt(2.0)), truth, &along, &across);
  EXPECT_NEAR(along, 0.03, 1e-12);
  EXPECT_NEAR(across, 0.0, 1e-12);
}

TEST(GapScoring, CountsWhereEachBollIsLost) {
  SceneLayout truth;
  const auto addTrue = [&truth](double u, double z) {
    TrueBoll b;
    const CameraIntrinsics k;
    b.pixel = cv::Point2d(u, k.cy);
    b.radius_px = 15.0;
    b.radius_m = 0.035;
    b.visible_fraction = 1.0;
    b.centre = cv::Point3d((u - k.cx) * z / k.fx, 0.0, z);
    b.surface = b.centre * (1.0 - b.radius_m / std::sqrt(b.centre.dot(b.centre)));
    truth.bolls.push_back(b);
  };
  for (int i = 0; i < 5; ++i) addTrue(200.0 + 200.0 * i, 1.5);
  FrameResult result;
  const auto located = [&](size_t b, double deeper) {
    LocatedBoll boll;
    boll.detection.centroid = truth.bolls[b].pixel;
    const cv::Point3d& s = truth.bolls[b].surface;
    boll.position = s * (1.0 + deeper / std::sqrt(s.dot(s)));
    boll.centre = centreBehindSurface(boll.position, 0.035);
    result.bolls.push_back(boll);
  };
  located(0, 0.0);    // found
  located(1, 0.05);   // 5 cm too deep
  located(2, -0.04);  // 4 cm too near
  FrameResult::Dropped dropped;
  dropped.detection.centroid = truth.bolls[3].pixel;
  dropped.no_depth = true;
  result.dropped.push_back(dropped);  // boll 3: no depth; boll 4: not detected
  // The cloud: depth on boll 0's disc only.
  cv::Mat cloud(720, 1280, CV_32FC3, cv::Scalar::all(std::numeric_limits<float>::quiet_NaN()));
  cv::circle(cloud, cv::Point(200, 361), 16, cv::Scalar(0.0, 0.0, 1.5), cv::FILLED);
  GapTable table;
  table.add(result, truth, cloud, 0.03);
  EXPECT_EQ(table.visible, 5);
  EXPECT_EQ(table.no_2d, 1);
  EXPECT_EQ(table.no_depth, 1);
  EXPECT_EQ(table.implausible, 0);
  EXPECT_EQ(table.located, 3);
  EXPECT_EQ(table.within, 1);
  EXPECT_EQ(table.centre_within, 1);
  ASSERT_EQ(table.along_m.size(), 3u);
  EXPECT_NEAR(table.along_m[0], 0.0, 1e-9);
  EXPECT_NEAR(table.along_m[1], 0.05, 1e-9);
  EXPECT_NEAR(table.along_m[2], -0.04, 1e-9);
  EXPECT_NEAR(table.across_m[1], 0.0, 1e-9);
  // Share bins: boll 0 has depth on its disc (>= 0.6), bolls 1-3 none (< 0.1).
  EXPECT_EQ(table.share_detected[3], 1);
  EXPECT_EQ(table.share_within[3], 1);
  EXPECT_EQ(table.share_detected[0], 3);
  EXPECT_EQ(table.share_located[0], 2);
  // A detector that returns nothing loses every boll in 2D.
  GapTable nothing;
  nothing.add(FrameResult{}, truth, cloud, 0.03);
  EXPECT_EQ(nothing.no_2d, 5);
  EXPECT_EQ(nothing.located, 0);
}

TEST(GapScoring, WithinDistanceOfCentreUsesTheCentreErrors) {
  FrameScore score;
  score.true_positives = 2;
  score.errors_3d_m = {0.01, 0.04};
  score.centre_errors_3d_m = {0.05, 0.01};
  score.matched_bolls = {0, 1};
  score.matched_detections = {0, 1};
  const FrameScore surface = withinDistance(score, 0.03);
  EXPECT_EQ(surface.true_positives, 1);
  EXPECT_EQ(surface.matched_bolls, std::vector<size_t>{0});
  const FrameScore centre = withinDistance(score, 0.03, true);
  EXPECT_EQ(centre.true_positives, 1);
  EXPECT_EQ(centre.matched_bolls, std::vector<size_t>{1});
  EXPECT_EQ(centre.matched_detections, std::vector<size_t>{1});
}
