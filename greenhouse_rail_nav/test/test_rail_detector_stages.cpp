// The rail detector's stages one by one: thinning, line candidates, partner search, pipe axis, start view.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "greenhouse_rail_nav/pipe_axis.h"
#include "greenhouse_rail_nav/rail_band.h"
#include "greenhouse_rail_nav/rail_line_candidates.h"
#include "greenhouse_rail_nav/rail_pair_selection.h"
#include "greenhouse_rail_nav/rail_start_view.h"

using namespace greenhouse_rail_nav;

namespace {

/// Points every 1 cm along x from x0 to x1 at (y, z) [m].
std::vector<Eigen::Vector3f> railPoints(double x0, double x1, double y, double z) {
  std::vector<Eigen::Vector3f> points;
  for (double x = x0; x <= x1 + 1e-9; x += 0.01)
    points.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  return points;
}

std::vector<int> allIndices(const std::vector<Eigen::Vector3f>& points) {
  std::vector<int> indices(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) indices[i] = static_cast<int>(i);
  return indices;
}

RailLine railAt(double x0, double x1, double y, double height) {
  const auto points = railPoints(x0, x1, y, height);
  RailLine rail = makeRailLine(xyOf(points));
  rail.height_m = height;
  return rail;
}

RailBand bandOf(const std::vector<Eigen::Vector3f>& points) {
  RailBand band;
  band.points = points;
  band.xy = xyOf(points);
  band.raw = points;
  return band;
}

}  // namespace

TEST(RailBand, ThinningKeepsOneMeanPointPerVoxel) {
  const std::vector<Eigen::Vector3f> points{{0.101f, 0.201f, 0.041f}, {0.109f, 0.209f, 0.049f}, {0.5f, 0.2f, 0.04f}};
  const auto thinned = thinToVoxels(points, 0.02);
  ASSERT_EQ(thinned.size(), 2u);
  EXPECT_NEAR(thinned[0].x(), 0.105f, 1e-6);  // voxels in the order of their x index
  EXPECT_NEAR(thinned[0].z(), 0.045f, 1e-6);
  EXPECT_NEAR(thinned[1].x(), 0.5f, 1e-6);
  EXPECT_EQ(thinToVoxels(points, 0.0).size(), 3u);  // off
  EXPECT_TRUE(thinToVoxels({}, 0.02).empty());
}

TEST(RailBand, MedianHeightAndXy) {
  const std::vector<Eigen::Vector3f> points{{1.0f, 2.0f, 0.05f}, {3.0f, 4.0f, 0.01f}, {5.0f, 6.0f, 0.03f}};
  EXPECT_NEAR(medianHeight(points, {0, 1, 2}), 0.03, 1e-6);
  EXPECT_NEAR(medianHeight(points, {0, 1}), 0.05, 1e-6);  // the upper one of an even count
  EXPECT_EQ(medianHeight(points, {}), 0.0);
  const auto xy = xyOf(points, {2, 0});
  ASSERT_EQ(xy.size(), 2u);
  EXPECT_EQ(xy[0], Eigen::Vector2d(5.0, 6.0));
  EXPECT_EQ(xy[1], Eigen::Vector2d(1.0, 2.0));
}

TEST(RailLineCandidates, AClusterAlongTheRobotIsARail) {
  const RailDetectorParams p;
  const auto band = railPoints(0.5, 1.5, 0.2, 0.04);
  const auto rail = railLineFromCluster(band, allIndices(band), p);
  ASSERT_TRUE(rail);
  EXPECT_NEAR(rail->fit.direction.x(), 1.0, 1e-6);
  EXPECT_NEAR(rail->fit.signedDistance({0.0, 0.0}), -0.2, 1e-6);
  EXPECT_NEAR(rail->height_m, 0.04, 1e-6);
  EXPECT_NEAR(rail->fit.centroid.x() + rail->near_end, 0.5, 1e-3);  // its start
  EXPECT_GT(rail->fit.linearity, 0.999);
}

TEST(RailLineCandidates, ShortTurnedOrBlobClustersAreNoRails) {
  const RailDetectorParams p;
  const auto short_rail = railPoints(0.5, 0.7, 0.2, 0.04);  // 0.2 m < min_line_length_m
  EXPECT_FALSE(railLineFromCluster(short_rail, allIndices(short_rail), p));
  std::vector<Eigen::Vector3f> turned;  // 60 degrees off the robot's heading
  for (double s = 0.0; s <= 1.0; s += 0.01)
    turned.emplace_back(static_cast<float>(0.5 + 0.5 * s), static_cast<float>(std::sqrt(3.0) / 2.0 * s), 0.04f);
  EXPECT_FALSE(railLineFromCluster(turned, allIndices(turned), p));
  std::vector<Eigen::Vector3f> blob;  // a square patch of leaves: not straight
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) blob.emplace_back(0.5f + 0.01f * i, 0.01f * j, 0.04f);
  EXPECT_FALSE(railLineFromCluster(blob, allIndices(blob), p));
}

TEST(RailLineCandidates, RansacLinesAreOrientedForwardAndVerticalOnesDropped) {
  const RailDetectorParams p;
  const auto band = railPoints(0.5, 1.5, -0.3, 0.05);
  RansacLine line;
  line.point = Eigen::Vector3f(1.0f, -0.3f, 0.05f);
  line.direction = Eigen::Vector3f(-1.0f, 0.0f, 0.0f);
  line.inliers = allIndices(band);
  const auto rail = railLineFromRansac(band, line, p);
  ASSERT_TRUE(rail);
  EXPECT_NEAR(rail->fit.direction.x(), 1.0, 1e-6);
  EXPECT_NEAR(rail->fit.centroid.y(), -0.3, 1e-6);
  EXPECT_NEAR(rail->height_m, 0.05, 1e-6);
  EXPECT_NEAR(rail->fit.length(), 1.0, 1e-3);
  line.direction = Eigen::Vector3f(0.0f, 0.0f, 1.0f);
  EXPECT_FALSE(railLineFromRansac(band, line, p));
}

TEST(RailLineCandidates, TwoRailsAmongTheClustersMostLinearFirst) {
  const RailDetectorParams p;
  auto band = railPoints(0.5, 1.5, -0.275, 0.04);
  for (const auto& q : railPoints(0.6, 1.6, 0.275, 0.04)) band.push_back(q);
  const RailLineCandidates candidates = clusterRailLines(band, p);
  EXPECT_EQ(candidates.groups, 2u);
  ASSERT_EQ(candidates.lines.size(), 2u);
  EXPECT_GE(candidates.lines[0].fit.linearity, candidates.lines[1].fit.linearity);
}

TEST(RailPairSelection, PartnerAmongLinesIsParallelAtTheGaugeAndHeight) {
  const RailDetectorParams p;
  const std::vector<RailLine> lines{railAt(0.5, 1.5, 0.275, 0.04), railAt(0.5, 1.5, 0.9, 0.04),
                                    railAt(0.5, 1.5, -0.27, 0.04), railAt(0.5, 1.5, -0.275, 0.08)};
  const auto partner = partnerAmongLines(lines, 0, p);
  ASSERT_TRUE(partner);
  EXPECT_EQ(*partner, 2u);  // 0.545 m away; the one at 0.55 m is 4 cm higher
  EXPECT_FALSE(partnerAmongLines({lines[0], lines[1]}, 0, p));
}

TEST(RailPairSelection, PartnerFromBandPointsAGaugeAway) {
  const RailDetectorParams p;
  const RailLine rail = railAt(0.5, 1.5, 0.275, 0.04);
  const RailBand band = bandOf(railPoints(0.5, 1.5, -0.275, 0.04));
  const auto partner = partnerFromBand(rail, band, p);
  ASSERT_TRUE(partner);
  EXPECT_NEAR(partner->fit.centroid.y(), -0.275, 1e-3);
  EXPECT_NEAR(partner->height_m, 0.04, 1e-6);
  EXPECT_FALSE(partnerFromBand(rail, bandOf(railPoints(0.5, 1.5, -0.1, 0.04)), p));    // nothing a gauge away
  EXPECT_FALSE(partnerFromBand(rail, bandOf(railPoints(0.5, 1.5, -0.275, 0.09)), p));  // not at its height
}

TEST(RailPairSelection, VarianceFloorsForPerfectLines) {
  const RailDetectorParams p;
  RailPair pair;
  pair.first = railAt(0.5, 1.5, 0.275, 0.04);
  pair.second = railAt(0.5, 1.5, -0.275, 0.04);
  const auto variance = railPairVariance(pair, thorvald_base::Pose2D(-0.5, 0.0, 0.0), p);
  EXPECT_NEAR(variance[0], p.sigma_x_m * p.sigma_x_m + p.voxel_size_m * p.voxel_size_m, 1e-12);
  EXPECT_NEAR(variance[1], p.sigma_y_m * p.sigma_y_m, 1e-9);
  EXPECT_NEAR(variance[2], p.sigma_yaw_rad * p.sigma_yaw_rad, 1e-9);
}

TEST(RailPairSelection, ChoosesTheSetUnderTheRobotNotTheNeighbour) {
  RailDetectorParams p;
  p.pipe_radius_m = 0.0;  // the lines are the axes
  const RailBand band;
  const Eigen::Vector3d camera(0.35, 0.0, 0.7);
  const std::vector<RailLine> own{railAt(0.5, 1.5, 0.275, 0.04), railAt(0.5, 1.5, -0.275, 0.04)};
  std::string why;
  const auto choice = selectRailPair(own, band, false, camera, p, &why);
  ASSERT_TRUE(choice) << why;
  EXPECT_NEAR(choice->pair.gauge_m, 0.55, 1e-6);
  EXPECT_NEAR(choice->pair.rail_in_base.y, 0.0, 1e-6);
  EXPECT_NEAR(choice->pair.rail_in_base.x, 0.5, 1e-3);
  const std::vector<RailLine> neighbour{railAt(0.5, 1.5, 0.6, 0.04), railAt(0.5, 1.5, 1.15, 0.04)};
  EXPECT_FALSE(selectRailPair(neighbour, band, false, camera, p, &why));
  EXPECT_NE(why.find("neighbouring rail set"), std::string::npos) << why;
  EXPECT_FALSE(selectRailPair({own[0]}, band, false, camera, p, &why));
  EXPECT_NE(why.find("beside any of 1 straight lines"), std::string::npos) << why;
}

TEST(PipeAxis, TheAxisLiesBehindTheVisibleSurface) {
  const double r = 0.0255, axis_y = 0.3, axis_z = 0.03;
  const Eigen::Vector3d camera(0.35, 0.0, 0.7);
  std::vector<Eigen::Vector3f> surface;  // the half of the pipe that faces the camera
  for (double x = 0.8; x <= 1.6; x += 0.01) {
    for (double a = 0.0; a < 2.0 * M_PI; a += M_PI / 36.0) {
      const Eigen::Vector3d normal(0.0, std::cos(a), std::sin(a));
      const Eigen::Vector3d q(x, axis_y + r * normal.y(), axis_z + r * normal.z());
      if (normal.dot(camera - q) > 0.0) surface.push_back(q.cast<float>());
    }
  }
  RailLine rail = makeRailLine(xyOf(surface));
  std::vector<int> all = allIndices(surface);
  rail.height_m = medianHeight(surface, all);
  EXPECT_LT(rail.fit.centroid.y(), axis_y - 0.003);  // the visible points lie nearer the camera
  const RailLine axis = pipeAxisLine(rail, camera, surface, r);
  EXPECT_NEAR(axis.fit.centroid.y(), axis_y, 0.002);
  EXPECT_NEAR(axis.fit.direction.x(), rail.fit.direction.x(), 1e-12);
  const RailLine unchanged = pipeAxisLine(rail, camera, surface, 0.0);
  EXPECT_EQ(unchanged.fit.centroid, rail.fit.centroid);
  // Without points near the line, the model offset of a half-cylinder.
  const RailLine model = pipeAxisLine(rail, camera, {}, r);
  EXPECT_GT(model.fit.centroid.y(), rail.fit.centroid.y());
}

TEST(RailStartView, FloorBeforeTheStartMustBeSeen) {
  const RailDetectorParams p;
  const std::vector<RailLine> rails{railAt(1.0, 2.0, 0.275, 0.04), railAt(1.0, 2.0, -0.275, 0.04)};
  const Eigen::Isometry3d camera_in_base = opticalFrameInBase(0.35, 0.0, 0.70, 0.70);
  const int cols = static_cast<int>(std::ceil(2.0 * p.crop_y_max_m / kFloorBinM));
  const int rows = static_cast<int>(std::ceil((p.crop_x_max_m - p.crop_x_min_m) / kFloorBinM));
  const std::vector<float> floor(static_cast<std::size_t>(rows * cols), 1.0f), no_floor(floor.size(), 0.0f);
  EXPECT_TRUE(railStartView(rails, floor, std::nullopt, camera_in_base, p).seen);
  const RailStartView hidden = railStartView(rails, no_floor, std::nullopt, camera_in_base, p);
  EXPECT_FALSE(hidden.seen);
  EXPECT_EQ(hidden.why, "no floor seen just before it");
  EXPECT_TRUE(floorSeen(floor, {1.0, 0.0}, p));
  EXPECT_FALSE(floorSeen(floor, {-1.0, 0.0}, p));  // behind the crop region
  EXPECT_FALSE(floorSeen(floor, {1.0, 2.0}, p));   // beside it
}

TEST(RailStartView, RailsCutByTheImageBorder) {
  const RailDetectorParams p;
  const Eigen::Isometry3d camera_in_base = opticalFrameInBase(0.35, 0.0, 0.70, 0.70);
  const std::optional<CloudProjection> projection = CloudProjection(DepthCameraIntrinsics{});
  const int cols = static_cast<int>(std::ceil(2.0 * p.crop_y_max_m / kFloorBinM));
  const int rows = static_cast<int>(std::ceil((p.crop_x_max_m - p.crop_x_min_m) / kFloorBinM));
  const std::vector<float> floor(static_cast<std::size_t>(rows * cols), 1.0f);
  const std::vector<RailLine> far{railAt(1.2, 2.2, 0.275, 0.04), railAt(1.2, 2.2, -0.275, 0.04)};
  EXPECT_TRUE(railStartView(far, floor, projection, camera_in_base, p).seen);
  const std::vector<RailLine> near{railAt(0.2, 2.2, 0.275, 0.04), railAt(0.2, 2.2, -0.275, 0.04)};
  const RailStartView cut = railStartView(near, floor, projection, camera_in_base, p);
  EXPECT_FALSE(cut.seen);
  EXPECT_EQ(cut.why, "the rails are cut by the image border");
}
