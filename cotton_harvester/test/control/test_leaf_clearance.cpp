// pointsOverApproach: the cloud points that tell a leaf lies over a boll along the end-effector's approach.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cotton_harvester/control/leaf_clearance.h"

using cotton_harvester::control::CloudView;
using cotton_harvester::control::LeafClearanceParams;
using cotton_harvester::control::pointsOverApproach;

namespace {

/// An organised cloud of `rows` x `cols` points on a 5 mm grid around x = -0.3..0.3, y = -0.15..0.15, all at
/// `ground_z`; `patch` sets z for the points inside a box.
struct GridCloud {
  int rows = 60, cols = 120;
  std::vector<float> xyz;
  explicit GridCloud(float ground_z) : xyz(static_cast<std::size_t>(rows) * cols * 3) {
    for (int v = 0; v < rows; ++v)
      for (int u = 0; u < cols; ++u) set(v, u, -0.3f + 0.005f * u, -0.15f + 0.005f * v, ground_z);
  }
  void set(int v, int u, float x, float y, float z) {
    float* p = &xyz[(static_cast<std::size_t>(v) * cols + u) * 3];
    p[0] = x, p[1] = y, p[2] = z;
  }
  float x(int u) const { return -0.3f + 0.005f * u; }
  float y(int v) const { return -0.15f + 0.005f * v; }
  void patch(float x0, float x1, float y0, float y1, float z) {
    for (int v = 0; v < rows; ++v)
      for (int u = 0; u < cols; ++u)
        if (x(u) >= x0 && x(u) <= x1 && y(v) >= y0 && y(v) <= y1) set(v, u, x(u), y(v), z);
  }
  CloudView view() const {
    CloudView c;
    c.data = reinterpret_cast<const std::uint8_t*>(xyz.data());
    c.rows = rows;
    c.cols = cols;
    c.point_step = 12;
    c.row_step = 12 * static_cast<std::size_t>(cols);
    return c;
  }
};

}  // namespace

TEST(LeafClearance, CountsALeafOverTheApproachOnly) {
  const LeafClearanceParams p;  // 6 cm above the boll's top, housing half side 5 cm
  GridCloud cloud(2.0f);        // ground far below
  const double depth = 1.50;    // the housing (and the boll's top) 1.50 m below the camera
  EXPECT_EQ(pointsOverApproach(cloud.view(), -0.2, 0.1, depth, p), 0);
  // A leaf 3 cm above the boll's top, 10 x 6 cm, between the housing and the boll: every second point of a 5 mm grid.
  cloud.patch(-0.05f, 0.05f, -0.03f, 0.03f, 1.47f);
  const int n = pointsOverApproach(cloud.view(), -0.2, 0.1, depth, p);
  EXPECT_GE(n, 40);
  EXPECT_LE(n, 21 * 13);
  // The same leaf beside the approach line (y beyond the housing's width), or above the sweep level: not counted.
  GridCloud beside(2.0f);
  beside.patch(-0.05f, 0.05f, 0.07f, 0.13f, 1.47f);
  EXPECT_EQ(pointsOverApproach(beside.view(), -0.2, 0.1, depth, p), 0);
  GridCloud high(2.0f);
  high.patch(-0.05f, 0.05f, -0.03f, 0.03f, 1.40f);
  EXPECT_EQ(pointsOverApproach(high.view(), -0.2, 0.1, depth, p), 0);
  // The housing's own top face (at the depth less the noise margin, around from_x) is not a leaf.
  GridCloud housing(2.0f);
  housing.patch(-0.25f, -0.15f, -0.05f, 0.05f, 1.47f);
  EXPECT_EQ(pointsOverApproach(housing.view(), -0.2, 0.1, depth, p), 0);
}

TEST(LeafClearance, BadInputCountsNothing) {
  const LeafClearanceParams p;
  GridCloud cloud(std::numeric_limits<float>::quiet_NaN());  // no depth anywhere
  EXPECT_EQ(pointsOverApproach(cloud.view(), -0.2, 0.1, 1.5, p), 0);
  GridCloud leaf(2.0f);
  leaf.patch(-0.05f, 0.05f, -0.03f, 0.03f, 1.47f);
  EXPECT_EQ(pointsOverApproach(leaf.view(), std::nan(""), 0.1, 1.5, p), 0);
  EXPECT_EQ(pointsOverApproach(leaf.view(), -0.2, 0.1, std::nan(""), p), 0);
  EXPECT_EQ(pointsOverApproach(CloudView(), -0.2, 0.1, 1.5, p), 0);
  LeafClearanceParams bad;
  EXPECT_TRUE(bad.check().empty());
  bad.leaf_points_min = 0;
  EXPECT_FALSE(bad.check().empty());
  bad = LeafClearanceParams();
  bad.leaf_clearance_m = -0.01;
  EXPECT_FALSE(bad.check().empty());
  bad = LeafClearanceParams();
  bad.effector_half_m = std::nan("");
  EXPECT_FALSE(bad.check().empty());
}
