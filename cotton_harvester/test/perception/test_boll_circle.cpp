// The boll's disc from its visible outline (fitOuterCircle), its depth from its visible surface (locateBollSurface)
// and partly hidden bolls accepted by the colour detector.

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/boll_circle.h"
#include "cotton_harvester/perception/boll_locator.h"
#include "cotton_harvester/perception/colour_boll_detector.h"

using namespace cotton_harvester::perception;

namespace {

const cv::Scalar kWhite(235, 238, 240);
const cv::Scalar kLeaf(40, 150, 50);

std::vector<cv::Point> largestOutline(const cv::Mat& mask) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  std::vector<cv::Point> best;
  for (const auto& c : contours)
    if (cv::contourArea(c) > cv::contourArea(best.empty() ? c : best) || best.empty()) best = c;
  return best;
}

cv::Point2d centroidOf(const std::vector<cv::Point>& outline) {
  const cv::Moments m = cv::moments(outline);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

/// A disc of radius r [px] at a sub-pixel centre (drawn with 8 bits of sub-pixel precision) with a leaf (ellipse)
/// over part of it; the visible fraction of the disc is returned.
double drawPartialDisc(cv::Mat* mask, const cv::Point2d& centre, double r, const cv::Point2d& leaf_centre,
                       const cv::Size& leaf_axes, double leaf_angle_deg) {
  constexpr int kShift = 8;
  const auto fixed = [](double x) { return static_cast<int>(std::lround(x * (1 << kShift))); };
  mask->setTo(0);
  cv::circle(*mask, {fixed(centre.x), fixed(centre.y)}, fixed(r), cv::Scalar(255), cv::FILLED, cv::LINE_8, kShift);
  const double whole = cv::countNonZero(*mask);
  cv::ellipse(*mask, cv::Point(cvRound(leaf_centre.x), cvRound(leaf_centre.y)), leaf_axes, leaf_angle_deg, 0, 360,
              cv::Scalar(0), cv::FILLED);
  return cv::countNonZero(*mask) / whole;
}

}  // namespace

TEST(BollCircle, FitsAWholeDiscAtASubPixelCentre) {
  cv::Mat mask(200, 200, CV_8U);
  for (double r : {6.0, 12.5, 30.0}) {
    const cv::Point2d centre(100.3, 97.6);
    drawPartialDisc(&mask, centre, r, {-100, -100}, {1, 1}, 0.0);
    const auto circle = fitOuterCircle(largestOutline(mask));
    ASSERT_TRUE(circle.has_value()) << r;
    EXPECT_NEAR(circle->centre.x, centre.x, 0.5) << r;
    EXPECT_NEAR(circle->centre.y, centre.y, 0.5) << r;
    EXPECT_NEAR(circle->radius_px, r, 1.0) << r;
    EXPECT_GT(circle->arc_coverage_rad, 1.9 * CV_PI);
    EXPECT_LT(circle->rms_px, 0.5);
  }
}

// Seeded random discs (radius 8-40 px) with a leaf over 30-60 % of them: the circle through the outline's hull
// points finds the centre within 1.5 px (and well within a tenth of the radius) where the visible centroid is off by
// a third of the radius or more.
TEST(BollCircle, FindsTheCentreOfPartlyHiddenDiscs) {
  cv::RNG rng(17);
  cv::Mat mask(240, 240, CV_8U);
  int cases = 0;
  double worst_fit = 0.0, worst_centroid_share = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 400 && cases < 60; ++trial) {
    const double r = rng.uniform(8.0, 40.0);
    const cv::Point2d centre(rng.uniform(110.0, 130.0), rng.uniform(110.0, 130.0));
    const double heading = rng.uniform(-CV_PI, CV_PI);
    const cv::Size axes(static_cast<int>(r * rng.uniform(1.2, 2.0)), static_cast<int>(r * rng.uniform(0.9, 1.4)));
    const double offset = axes.width + r * rng.uniform(-0.5, 0.4);
    const cv::Point2d leaf = centre + offset * cv::Point2d(std::cos(heading), std::sin(heading));
    const double visible = drawPartialDisc(&mask, centre, r, leaf, axes, heading * 180.0 / CV_PI);
    if (visible < 0.4 || visible > 0.7) continue;
    ++cases;
    const std::vector<cv::Point> outline = largestOutline(mask);
    const auto circle = fitOuterCircle(outline);
    ASSERT_TRUE(circle.has_value());
    const double fit_error = cv::norm(circle->centre - centre);
    EXPECT_LT(fit_error, std::max(1.5, 0.1 * r)) << "r " << r << " visible " << visible;
    EXPECT_NEAR(circle->radius_px, r, std::max(1.5, 0.1 * r));
    worst_fit = std::max(worst_fit, fit_error / r);
    worst_centroid_share = std::min(worst_centroid_share, cv::norm(centroidOf(outline) - centre) / r);
  }
  EXPECT_GE(cases, 40);
  EXPECT_LT(worst_fit, 0.1);
  EXPECT_GT(worst_centroid_share, 0.15);  // the centroid alone would be far off: the test can tell them apart
}

TEST(BollCircle, DiscCutByTheImageBorder) {
  cv::Mat mask(100, 200, CV_8U, cv::Scalar(0));
  cv::circle(mask, {60, 8}, 20, cv::Scalar(255), cv::FILLED);  // 12 px of its 20 px radius above the image
  const auto circle = fitOuterCircle(largestOutline(mask));
  ASSERT_TRUE(circle.has_value());
  EXPECT_NEAR(circle->centre.x, 60.0, 1.0);
  EXPECT_NEAR(circle->centre.y, 8.0, 1.5);
  EXPECT_NEAR(circle->radius_px, 20.0, 1.5);
}

TEST(BollCircle, ElongatedShapesAreNotRound) {
  cv::Mat mask(200, 200, CV_8U, cv::Scalar(0));
  cv::ellipse(mask, {100, 100}, {40, 10}, 30, 0, 360, cv::Scalar(255), cv::FILLED);  // a glint on a leaf
  const auto glint = fitOuterCircle(largestOutline(mask));
  ASSERT_TRUE(glint.has_value());
  EXPECT_GT(glint->rms_px, 0.08 * glint->radius_px);
  mask.setTo(0);
  cv::rectangle(mask, cv::Rect(50, 50, 60, 20), cv::Scalar(255), cv::FILLED);  // a piece of the arm
  // Its straight sides are cuts; its corners lie on a circle but cover no arc of it.
  const auto bar = fitOuterCircle(largestOutline(mask));
  EXPECT_TRUE(!bar.has_value() || bar->arc_coverage_rad < 0.5);
}

TEST(BollCircle, DegenerateInput) {
  EXPECT_FALSE(fitOuterCircle({}).has_value());
  EXPECT_FALSE(fitOuterCircle({{1, 1}, {2, 2}, {3, 3}, {4, 4}, {5, 5}, {6, 6}}).has_value());
  EXPECT_FALSE(fitCircle({{0, 0}, {1, 1}}).has_value());
  const auto circle = fitCircle({{10, 0}, {0, 10}, {-10, 0}, {0, -10}});
  ASSERT_TRUE(circle.has_value());
  EXPECT_NEAR(circle->radius_px, 10.0, 1e-9);
  EXPECT_NEAR(circle->arc_coverage_rad, 0.0, 1e-9);  // four isolated points cover no arc
}

namespace {

/// Organised cloud of a sphere (centre c, radius R) over a ground plane at ground_z, with a flat leaf (a disc of
/// radius leaf_r at leaf_c, facing the camera) above it; range noise sigma = noise_k z^2, seeded. Also returns the
/// mask of the sphere's visible pixels.
cv::Mat sphereCloud(const CameraIntrinsics& k, const cv::Point3d& c, double R, const cv::Point3d& leaf_c, double leaf_r,
                    double ground_z, double noise_k, cv::Mat* visible) {
  cv::RNG rng(5);
  cv::Mat cloud(k.height, k.width, CV_32FC3);
  *visible = cv::Mat::zeros(k.height, k.width, CV_8U);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      cv::Vec3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      ray /= cv::norm(ray);
      double t = ground_z / ray[2];
      bool on_sphere = false;
      const double b = ray.dot(cv::Vec3d(c.x, c.y, c.z));
      const double disc = b * b - (c.dot(c) - R * R);
      if (disc >= 0.0 && b - std::sqrt(disc) < t) {
        t = b - std::sqrt(disc);
        on_sphere = true;
      }
      const double t_leaf = leaf_c.z / ray[2];
      const cv::Vec3d at_leaf = ray * t_leaf;
      if (t_leaf < t && std::hypot(at_leaf[0] - leaf_c.x, at_leaf[1] - leaf_c.y) <= leaf_r) {
        t = t_leaf;
        on_sphere = false;
      }
      const cv::Vec3d p = ray * t;
      t += noise_k * p[2] * p[2] * rng.gaussian(1.0);
      const cv::Vec3d noisy = ray * t;
      cloud.at<cv::Vec3f>(v, u) = cv::Vec3f(float(noisy[0]), float(noisy[1]), float(noisy[2]));
      if (on_sphere) visible->at<uint8_t>(v, u) = 255;
    }
  }
  return cloud;
}

}  // namespace

// A boll 1.6 m from the camera with a leaf over its centre: its depth from the visible surface lands on the true
// surface point on its centre's ray (within 3 mm with the stereo noise of the synthetic frames, sigma 5 mm here);
// the window at the visible centroid is off by the sphere's curvature (and by its offset from the centre).
TEST(BollSurface, PartlyHiddenSphereLocatedAtItsSurfaceOnTheCentreRay) {
  const CameraIntrinsics k;
  const cv::Point3d centre(0.15, -0.10, 1.60);
  const double R = 0.035;
  const cv::Point3d leaf(centre.x + 0.04, centre.y + 0.01, centre.z - R - 0.03);
  cv::Mat visible;
  const cv::Mat cloud = sphereCloud(k, centre, R, leaf, 0.045, 2.2, 0.002, &visible);
  const std::vector<cv::Point> outline = largestOutline(visible);
  ASSERT_FALSE(outline.empty());
  const auto circle = fitOuterCircle(outline);
  ASSERT_TRUE(circle.has_value());
  const cv::Point2d true_pixel = project(k, centre);
  EXPECT_LT(cv::norm(circle->centre - true_pixel), 1.5);

  const cv::Point3d surface = centre - R * centre / std::sqrt(centre.dot(centre));
  const auto located = locateBollSurface(cloud, outline, circle->centre, circle->radius_px, k, LocatorParams{});
  ASSERT_TRUE(located.has_value());
  const double error = cv::norm(located->position - surface);
  EXPECT_LT(error, 0.003);
  EXPECT_GT(located->valid_points, 100);
  // The 5x5 window at the visible centroid, for comparison.
  const auto window = locate(cloud, centroidOf(outline), k, LocatorParams{});
  ASSERT_TRUE(window.has_value());
  EXPECT_GT(cv::norm(window->position - surface), error);
}

TEST(BollSurface, NoiseFreeSphereExactlyAtItsSurface) {
  const CameraIntrinsics k;
  const cv::Point3d centre(-0.30, 0.20, 1.20);
  const double R = 0.04;
  cv::Mat visible;
  const cv::Mat cloud = sphereCloud(k, centre, R, {0, 0, 0.5}, 0.0, 2.2, 0.0, &visible);
  const std::vector<cv::Point> outline = largestOutline(visible);
  const auto circle = fitOuterCircle(outline);
  ASSERT_TRUE(circle.has_value());
  const auto located = locateBollSurface(cloud, outline, circle->centre, circle->radius_px, k, LocatorParams{});
  ASSERT_TRUE(located.has_value());
  const cv::Point3d surface = centre - R * centre / std::sqrt(centre.dot(centre));
  EXPECT_LT(cv::norm(located->position - surface), 0.0015);
}

TEST(BollSurface, BadInput) {
  const CameraIntrinsics k;
  cv::Mat cloud(k.height, k.width, CV_32FC3, cv::Scalar(0, 0, 1.5f));
  const std::vector<cv::Point> square{{100, 100}, {120, 100}, {120, 120}, {100, 120}};
  const LocatorParams p;
  EXPECT_FALSE(locateBollSurface(cv::Mat(), square, {110, 110}, 10, k, p).has_value());
  EXPECT_FALSE(locateBollSurface(cloud, square, {NAN, 110}, 10, k, p).has_value());
  EXPECT_FALSE(locateBollSurface(cloud, square, {110, 110}, 0.0, k, p).has_value());
  EXPECT_FALSE(locateBollSurface(cloud, {}, {110, 110}, 10, k, p).has_value());
  EXPECT_FALSE(locateBollSurface(cloud, {{-50, -50}, {-40, -50}, {-40, -40}}, {110, 110}, 10, k, p).has_value());
  // All NaN under the outline: too few valid points.
  cloud.setTo(cv::Scalar::all(std::numeric_limits<float>::quiet_NaN()));
  EXPECT_FALSE(locateBollSurface(cloud, square, {110, 110}, 10, k, p).has_value());
}

// The dome of the visible surface: a sphere's rim lies about half its radius deeper than its centre, a flat patch's
// (facing the camera or tilted 35 degrees, a label on a leaning stake) does not, with the synthetic frames' stereo
// noise; too few valid points leave the dome unmeasured (NaN) without losing the location.
TEST(BollSurface, DomeOfASphereAndOfFlatPatches) {
  const CameraIntrinsics k;
  const cv::Point3d centre(0.15, -0.10, 1.60);
  const double R = 0.035;
  cv::Mat visible;
  const cv::Mat sphere = sphereCloud(k, centre, R, {0, 0, 0.5}, 0.0, 2.2, 0.002, &visible);
  const std::vector<cv::Point> outline = largestOutline(visible);
  const auto circle = fitOuterCircle(outline);
  ASSERT_TRUE(circle.has_value());
  const auto domed = locateBollSurface(sphere, outline, circle->centre, circle->radius_px, k, LocatorParams{});
  ASSERT_TRUE(domed.has_value());
  const double radius_m = circle->radius_px * domed->position.z / k.fx;
  EXPECT_GT(domed->dome_m, 0.35 * radius_m);
  EXPECT_LT(domed->dome_m, 0.8 * radius_m);
  EXPECT_LT(domed->dome_sigma_m, 0.1 * radius_m);

  // The same disc in the image, its points on a plane at the sphere's apex depth: facing the camera, then tilted.
  const double apex_z = centre.z - R;
  for (const double tilt_deg : {0.0, 35.0}) {
    cv::RNG rng(11);
    cv::Mat flat(k.height, k.width, CV_32FC3);
    const double slope = std::tan(tilt_deg * CV_PI / 180.0);
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u) {
        // The plane z = apex_z + slope (x - centre.x), met by the pixel's ray (x = rx z).
        const double rx = (u - k.cx) / k.fx, ry = (v - k.cy) / k.fy;
        double z = (apex_z - slope * centre.x) / (1.0 - slope * rx);
        z += 0.002 * z * z * rng.gaussian(1.0);
        flat.at<cv::Vec3f>(v, u) = cv::Vec3f(float(rx * z), float(ry * z), float(z));
      }
    const auto patch = locateBollSurface(flat, outline, circle->centre, circle->radius_px, k, LocatorParams{});
    ASSERT_TRUE(patch.has_value()) << tilt_deg;
    EXPECT_LT(std::abs(patch->dome_m), 0.1 * radius_m) << tilt_deg;
    EXPECT_LT(patch->dome_sigma_m, 0.1 * radius_m) << tilt_deg;
  }

  // Only a few valid points under the outline: located, dome not measured.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat sparse(k.height, k.width, CV_32FC3, cv::Scalar::all(nan));
  const cv::Point c(cvRound(circle->centre.x), cvRound(circle->centre.y));
  for (int i = -2; i <= 2; ++i) {
    sparse.at<cv::Vec3f>(c.y + i, c.x) = sphere.at<cv::Vec3f>(c.y + i, c.x);
    sparse.at<cv::Vec3f>(c.y, c.x + i) = sphere.at<cv::Vec3f>(c.y, c.x + i);
  }
  const auto few = locateBollSurface(sparse, outline, circle->centre, circle->radius_px, k, LocatorParams{});
  ASSERT_TRUE(few.has_value());
  EXPECT_TRUE(std::isnan(few->dome_m));
  EXPECT_TRUE(std::isnan(few->dome_sigma_m));
}

// A boll that touches another one nearer the camera in the image: the split gives it some of the near boll's pixels
// (a fifth of its disc here, 25 cm nearer). Those lie farther from the surface's median depth than a boll's cap
// spans and are left out of the dome fit: the dome stays a sphere's instead of turning deeply negative (a boll whose
// rim seems nearer than its centre), which the dome test would take for no boll at all.
TEST(BollSurface, DomeIgnoresANearerBollUnderTheOutline) {
  const CameraIntrinsics k;
  const cv::Point3d centre(0.15, -0.10, 1.60);
  const double R = 0.035;
  cv::Mat visible;
  cv::Mat cloud = sphereCloud(k, centre, R, {0, 0, 0.5}, 0.0, 2.2, 0.002, &visible);
  const std::vector<cv::Point> outline = largestOutline(visible);
  const auto circle = fitOuterCircle(outline);
  ASSERT_TRUE(circle.has_value());
  cv::RNG rng(3);
  const double near_z = centre.z - R - 0.25;
  int moved = 0, inside = 0;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      if (!visible.at<uint8_t>(v, u)) continue;
      ++inside;
      if (u < circle->centre.x + 0.45 * circle->radius_px) continue;
      const double z = near_z + 0.002 * near_z * near_z * rng.gaussian(1.0);
      cloud.at<cv::Vec3f>(v, u) = cv::Vec3f(float((u - k.cx) / k.fx * z), float((v - k.cy) / k.fy * z), float(z));
      ++moved;
    }
  ASSERT_GT(moved, inside / 6);
  const auto located = locateBollSurface(cloud, outline, circle->centre, circle->radius_px, k, LocatorParams{});
  ASSERT_TRUE(located.has_value());
  const double radius_m = circle->radius_px * (centre.z - R) / k.fx;
  EXPECT_GT(located->dome_m, 0.35 * radius_m);
  EXPECT_LT(located->dome_m, 0.8 * radius_m);
  // Still located on the boll's own surface (the median of its points), not between the two.
  EXPECT_NEAR(located->position.z, centre.z - R, 0.01);
}

// Crescents past a leaf fail the whole-boll shape tests (solidity, circularity) but their own silhouette is a boll's
// arc: accepted with their centre and radius; a glint on a leaf is not round and stays out.
TEST(ColourBollDetector, PartlyHiddenBollAcceptedForItsRoundSilhouette) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  const cv::Point2d first(400, 300), second(800, 300);
  cv::circle(image, cv::Point(first), 24, kWhite, cv::FILLED);               // a boll ...
  cv::circle(image, {412, 300}, 20, kLeaf, cv::FILLED);                      // ... a leaf over its right part
  cv::circle(image, cv::Point(second), 18, kWhite, cv::FILLED);              // a smaller boll ...
  cv::circle(image, {800, 290}, 15, kLeaf, cv::FILLED);                      // ... a leaf over its top
  cv::ellipse(image, {1000, 300}, {40, 8}, 25, 0, 360, kWhite, cv::FILLED);  // a glint on a leaf
  cv::Mat white;
  cv::inRange(image, kWhite, kWhite, white);
  const double first_visible = cv::countNonZero(white(cv::Rect(370, 270, 60, 60))) / (CV_PI * 24 * 24);
  const double second_visible = cv::countNonZero(white(cv::Rect(780, 280, 40, 40))) / (CV_PI * 18 * 18);
  ASSERT_GT(first_visible, 0.35);
  ASSERT_LT(first_visible, 0.6);
  ASSERT_GT(second_visible, 0.35);
  ASSERT_LT(second_visible, 0.6);

  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 2u);
  for (const BollDetection& b : bolls) {
    EXPECT_TRUE(b.partial);
    EXPECT_FALSE(b.outline.empty());
    const bool is_first = b.centroid.x < 600;
    const cv::Point2d truth = is_first ? first : second;
    EXPECT_LT(cv::norm(b.centre - truth), 2.0) << truth;
    EXPECT_NEAR(b.radius_px, is_first ? 24.5 : 18.5, 2.0) << truth;
    EXPECT_GT(cv::norm(b.centroid - truth), 5.0) << truth;  // the visible centroid is off the centre
    EXPECT_GT(b.confidence, 0.3);
  }
  // Off: the same frame gives nothing (both fail the whole-boll shape tests).
  ColourBollParams off;
  off.partial_min_visible = 0.0;
  EXPECT_TRUE(ColourBollDetector{off}.detect(image, cv::Mat()).empty());
  // Less visible than asked: not a boll.
  ColourBollParams strict;
  strict.partial_min_visible = 0.7;
  EXPECT_TRUE(ColourBollDetector{strict}.detect(image, cv::Mat()).empty());
  off.partial_min_visible = 1.5;
  EXPECT_THROW(ColourBollDetector{off}, std::invalid_argument);
}

TEST(ColourBollDetector, WholeBollsCarryTheirDisc) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {300, 200}, 15, kWhite, cv::FILLED);
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_FALSE(bolls[0].partial);
  EXPECT_LT(cv::norm(bolls[0].centre - cv::Point2d(300, 200)), 0.5);
  EXPECT_NEAR(bolls[0].radius_px, 15.5, 1.0);
}
