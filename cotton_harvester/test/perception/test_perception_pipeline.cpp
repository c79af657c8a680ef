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

  /// A boll is a sphere whose nearest point to the lens lies on the ray through the disc's centre at depth d.z, its
  /// radius the disc's at that distance; the depth of each pixel is where its ray meets the sphere.
  void addBoll(const Disc& d) {
    cv::circle(image, d.centre, d.radius_px, cv::Scalar(235, 238, 240), cv::FILLED);
    const CameraIntrinsics k;
    const auto ray = [&k](double u, double v) {
      const cv::Vec3d r((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      return r / cv::norm(r);
    };
    const cv::Vec3d axis = ray(d.centre.x, d.centre.y);
    const double apex = d.z / axis[2], radius = apex * d.radius_px / k.fx;
    const cv::Vec3d centre = axis * (apex + radius);
    for (int v = d.centre.y - d.radius_px - 2; v <= d.centre.y + d.radius_px + 2; ++v)
      for (int u = d.centre.x - d.radius_px - 2; u <= d.centre.x + d.radius_px + 2; ++u) {
        const cv::Vec3d r = ray(u, v);
        const double b = r.dot(centre), disc = b * b - (centre.dot(centre) - radius * radius);
        if (disc >= 0.0) depth.at<double>(v, u) = (b - std::sqrt(disc)) * r[2];
      }
  }
  /// A flat white disc (a label, a fold of a bag) of a boll's size: the plane z = d.z + slope (x - x of its centre).
  void addFlatPatch(const Disc& d, double slope = 0.0) {
    cv::circle(image, d.centre, d.radius_px, cv::Scalar(235, 238, 240), cv::FILLED);
    const CameraIntrinsics k;
    const double x0 = (d.centre.x - k.cx) / k.fx * d.z;
    for (int v = d.centre.y - d.radius_px - 2; v <= d.centre.y + d.radius_px + 2; ++v)
      for (int u = d.centre.x - d.radius_px - 2; u <= d.centre.x + d.radius_px + 2; ++u)
        if (std::hypot(u - d.centre.x, v - d.centre.y) <= d.radius_px + 0.5)
          depth.at<double>(v, u) = (d.z - slope * x0) / (1.0 - slope * (u - k.cx) / k.fx);
  }
  void addEndEffector(const cv::Rect& r, double z) {
    cv::rectangle(image, r, cv::Scalar(10, 120, 245), cv::FILLED);
    cv::rectangle(depth, r, cv::Scalar(z), cv::FILLED);
  }
  /// noise_k > 0: stereo-like depth noise of sigma noise_k z^2 (seeded).
  cv::Mat cloud(double noise_k = 0.0) const {
    const CameraIntrinsics k;
    cv::RNG rng(3);
    cv::Mat points(720, 1280, CV_32FC3);
    for (int v = 0; v < 720; ++v)
      for (int u = 0; u < 1280; ++u) {
        double z = depth.at<double>(v, u);
        if (noise_k > 0.0) z += noise_k * z * z * rng.gaussian(1.0);
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
    // Located at the boll's disc centre (for these whole discs within half a pixel of the centroid).
    EXPECT_LT(cv::norm(boll.detection.centre - boll.detection.centroid), 0.5);
    const double u = boll.detection.centre.x, v = boll.detection.centre.y;
    const double z = boll.position.z;
    EXPECT_NEAR(boll.position.x, (u - k.cx) / k.fx * z, 1e-3);
    EXPECT_NEAR(boll.position.y, (v - k.cy) / k.fy * z, 1e-3);
    if (std::abs(u - 400) < 2) {
      EXPECT_NEAR(z, 1.2, 1e-3);
    }
    if (std::abs(u - 1200) < 2) {
      // 36 degrees off the optical axis the sphere's image is an ellipse, not the fitted circle: 2 mm.
      EXPECT_NEAR(z, 1.3, 2e-3);
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

// A boll's visible surface bulges towards the camera; white things as large as a boll at their depth and above the
// ground but flat (facing the camera, or tilted 30 degrees as a label on a leaning stake) are dropped, with the
// synthetic frames' stereo noise. Without the dome test (boll_min_dome_fraction 0) all three pass.
TEST(PerceptionPipeline, FlatWhitePatchesOfABollsSizeAreNotBolls) {
  HandMadeFrame frame;
  frame.addBoll({{400, 300}, 16, 1.2});
  frame.addFlatPatch({{800, 300}, 16, 1.2});
  frame.addFlatPatch({{600, 500}, 14, 1.4}, std::tan(30.0 * CV_PI / 180.0));
  const cv::Mat cloud = frame.cloud(0.002);
  PerceptionPipeline pipeline = makePipeline();
  const FrameResult result = pipeline.process(frame.image, cloud);
  ASSERT_EQ(result.status, FrameStatus::kOk);
  EXPECT_EQ(result.bolls_detected, 3);
  ASSERT_EQ(result.bolls.size(), 1u);
  EXPECT_NEAR(result.bolls[0].detection.centre.x, 400.0, 1.0);
  EXPECT_NEAR(result.bolls[0].position.z, 1.2, 0.01);
  EXPECT_GT(result.bolls[0].dome_m, 0.2 * 0.0274);  // radius at 1.2 m: 16 px x 1.2 m / 699.9 px
  EXPECT_EQ(result.bolls_implausible, 2);

  PerceptionParams off;
  off.boll_min_dome_fraction = 0.0;
  PerceptionPipeline without(off, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  EXPECT_EQ(without.process(frame.image, cloud).bolls.size(), 3u);

  // Depth only at a few points of each: the dome cannot be measured and nothing is dropped for it.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat sparse(cloud.size(), CV_32FC3, cv::Scalar::all(nan));
  for (const cv::Point c : {cv::Point(400, 300), cv::Point(800, 300), cv::Point(600, 500)})
    for (int i = -2; i <= 2; ++i) {
      sparse.at<cv::Vec3f>(c.y + i, c.x) = cloud.at<cv::Vec3f>(c.y + i, c.x);
      sparse.at<cv::Vec3f>(c.y, c.x + i) = cloud.at<cv::Vec3f>(c.y, c.x + i);
    }
  // (Too few points for the cloud's ground: the nominal ground is used for the height test.)
  const FrameResult few = pipeline.process(frame.image, sparse);
  EXPECT_EQ(few.bolls.size(), 3u);
  for (const LocatedBoll& boll : few.bolls) EXPECT_TRUE(std::isnan(boll.dome_m));
  // No valid depth at all: nothing located, nothing breaks.
  const FrameResult none = pipeline.process(frame.image, cv::Mat(cloud.size(), CV_32FC3, cv::Scalar::all(nan)));
  EXPECT_TRUE(none.bolls.empty());
  EXPECT_EQ(none.bolls_without_depth, 3);
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
  for (const double fraction : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    PerceptionParams dome;
    dome.boll_min_dome_fraction = fraction;
    EXPECT_THROW(PerceptionPipeline(dome, std::make_unique<ColourBollDetector>(ColourBollParams{})),
                 std::invalid_argument);
  }
  PerceptionParams sigmas;
  sigmas.boll_dome_sigmas = -1.0;
  EXPECT_THROW(PerceptionPipeline(sigmas, std::make_unique<ColourBollDetector>(ColourBollParams{})),
               std::invalid_argument);
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

namespace {

/// The pixel box of a square housing top face of half side `half_m` centred at camera point (x, y, z).
cv::Rect housingBox(double x, double y, double z, double half_m) {
  const CameraIntrinsics k;
  const auto u = [&](double xm) { return static_cast<int>(std::lround(k.cx + k.fx * xm / z)); };
  const auto v = [&](double ym) { return static_cast<int>(std::lround(k.cy + k.fy * ym / z)); };
  return cv::Rect(cv::Point(u(x - half_m), v(y - half_m)), cv::Point(u(x + half_m), v(y + half_m)));
}

/// A frame with the housing (10 cm square, 1.50 m down, x = -0.20 m) and a terracotta pot: a larger orange-brown disc
/// on the ground, 2.00 m down, where the whole-image search finds it as the largest orange region.
HandMadeFrame housingAndPot() {
  HandMadeFrame frame;
  frame.addEndEffector(housingBox(-0.20, 0.0, 1.50, 0.05), 1.50);
  cv::circle(frame.image, {900, 250}, 36, cv::Scalar(31, 64, 180), cv::FILLED);  // hue ~ 10, saturated
  cv::circle(frame.depth, {900, 250}, 36, cv::Scalar(2.0), cv::FILLED);
  return frame;
}

}  // namespace

TEST(PerceptionPipeline, TheWholeImageSearchTakesTheLargestOrangeRegion) {
  const HandMadeFrame frame = housingAndPot();
  PerceptionPipeline pipeline = makePipeline();
  const FrameResult r = pipeline.process(frame.image, frame.cloud());
  ASSERT_TRUE(r.end_effector.has_value());
  EXPECT_NEAR(r.end_effector->position.z, 2.0, 0.02);  // the pot: why the search is restricted when it can be
}

TEST(PerceptionPipeline, WithTheArmsPriorTheHousingIsFoundAndThePotRefused) {
  const HandMadeFrame frame = housingAndPot();
  PerceptionPipeline pipeline = makePipeline();
  EndEffectorPrior prior;
  prior.position = {-0.17, 0.02, 1.53};  // the stepper counters: 3 to 4 cm off in each axis
  prior.radius_m = 0.08;
  const FrameResult r = pipeline.process(frame.image, frame.cloud(), prior);
  ASSERT_TRUE(r.end_effector.has_value());
  // Independent expectation: the housing's centre as drawn, within a pixel's rounding at 1.5 m (about 2 mm).
  EXPECT_NEAR(r.end_effector->position.x, -0.20, 0.005);
  EXPECT_NEAR(r.end_effector->position.y, 0.0, 0.005);
  EXPECT_NEAR(r.end_effector->position.z, 1.50, 0.005);
  EXPECT_EQ(r.end_effector_candidates, 1);  // the pot lies outside the box the arm can cover
  EXPECT_EQ(r.end_effector_candidates_refused, 0);
}

TEST(PerceptionPipeline, APotWhereTheArmCouldBeIsRefusedByDepthAndSize) {
  HandMadeFrame frame;
  // The arm is low over a pot: both in the search box; the housing is hidden (a leaf), only the pot shows.
  const cv::Rect pot = housingBox(0.0, 0.0, 2.0, 0.10);
  cv::ellipse(frame.image, (pot.tl() + pot.br()) / 2, pot.size() / 2, 0, 0, 360, cv::Scalar(31, 64, 180), cv::FILLED);
  cv::ellipse(frame.depth, (pot.tl() + pot.br()) / 2, pot.size() / 2, 0, 0, 360, cv::Scalar(2.0), cv::FILLED);
  PerceptionPipeline pipeline = makePipeline();
  EndEffectorPrior prior;
  prior.position = {0.02, 0.0, 1.90};
  prior.radius_m = 0.08;  // the pot's top is 10 cm deeper than the arm: refused
  const FrameResult r = pipeline.process(frame.image, frame.cloud(), prior);
  EXPECT_FALSE(r.end_effector.has_value());
  EXPECT_FALSE(r.end_effector_image.has_value());
  EXPECT_EQ(r.end_effector_candidates, 1);
  EXPECT_EQ(r.end_effector_candidates_refused, 1);
  // A generous radius lets its depth pass; its size (four times the housing's top face) still refuses it.
  prior.radius_m = 0.15;
  const FrameResult wide = pipeline.process(frame.image, frame.cloud(), prior);
  EXPECT_FALSE(wide.end_effector.has_value());
  EXPECT_EQ(wide.end_effector_candidates_refused, 1);
}

TEST(PerceptionPipeline, AnInvalidPriorFallsBackToTheWholeImage) {
  const HandMadeFrame frame = housingAndPot();
  PerceptionPipeline pipeline = makePipeline();
  EndEffectorPrior prior;
  prior.position = {std::numeric_limits<double>::quiet_NaN(), 0.0, 1.5};
  EXPECT_FALSE(validate(prior).empty());
  const FrameResult r = pipeline.process(frame.image, frame.cloud(), prior);
  ASSERT_TRUE(r.end_effector.has_value());
  EXPECT_EQ(r.end_effector_candidates, 0);
  prior.position = {-0.2, 0.0, 1.5};
  prior.radius_m = 0.0;
  EXPECT_FALSE(validate(prior).empty());
}

namespace {

LocatedBoll bollAt(double x, double y, double z, bool reachable) {
  LocatedBoll b;
  b.position = {x, y, z};
  b.range_m = std::sqrt(x * x + y * y + z * z);
  b.reachable = reachable;
  return b;
}

}  // namespace

TEST(NearestReachable, ByRangeFromTheLensSkippingUnreachableBolls) {
  const std::vector<LocatedBoll> bolls = {bollAt(0.0, 0.0, 1.2, false), bollAt(0.3, 0.0, 1.6, true),
                                          bollAt(-0.1, 0.0, 1.5, true)};
  EXPECT_EQ(nearestReachable(bolls, std::nullopt, NearestBy::kCamera), 2);
  LocatedPoint effector;
  effector.position = {0.3, 0.0, 1.55};
  // By range even with an end-effector, unless asked to measure from it.
  EXPECT_EQ(nearestReachable(bolls, effector, NearestBy::kCamera), 2);
  EXPECT_EQ(nearestReachable(bolls, effector, NearestBy::kEndEffector), 1);
  // Asked to measure from the end-effector but it is not located: from the lens.
  EXPECT_EQ(nearestReachable(bolls, std::nullopt, NearestBy::kEndEffector), 2);
}

TEST(NearestReachable, NoneReachableOrNoBolls) {
  EXPECT_EQ(nearestReachable({}, std::nullopt, NearestBy::kCamera), -1);
  EXPECT_EQ(nearestReachable({bollAt(0.0, 0.0, 1.0, false)}, std::nullopt, NearestBy::kCamera), -1);
  // The first of two at the same range.
  EXPECT_EQ(
      nearestReachable({bollAt(0.1, 0.0, 1.4, true), bollAt(-0.1, 0.0, 1.4, true)}, std::nullopt, NearestBy::kCamera),
      0);
}
