// The exact depth of a pixel's ray on spheres, capsules, cylinders and ellipsoids (the camera's curved geoms), against
// intersections worked out by hand and MuJoCo's.
#include <gtest/gtest.h>

#include "../src/curved_depth.h"

namespace {

using thorvald_sim::curvedDepth;
using V = Eigen::Vector3d;

constexpr double kTol = 1e-12;  // [m] closed-form roots of exactly representable inputs

TEST(CurvedDepth, SphereNearSideAndDepthAlongTheRay) {
  const double size[3] = {1.0, 0, 0};
  EXPECT_NEAR(curvedDepth(mjGEOM_SPHERE, size, V(0, 0, -5), V(0, 0, 1)), 4.0, kTol);
  // t is in units of the ray: a ray twice as long reaches the surface at half the t.
  EXPECT_NEAR(curvedDepth(mjGEOM_SPHERE, size, V(0, 0, -5), V(0, 0, 2)), 2.0, kTol);
  // From inside: the far side.
  EXPECT_NEAR(curvedDepth(mjGEOM_SPHERE, size, V(0, 0, 0), V(1, 0, 0)), 1.0, kTol);
}

TEST(CurvedDepth, SphereMissedOrBehindIsMinusOne) {
  const double size[3] = {1.0, 0, 0};
  EXPECT_EQ(curvedDepth(mjGEOM_SPHERE, size, V(0, 2, -5), V(0, 0, 1)), -1.0);
  EXPECT_EQ(curvedDepth(mjGEOM_SPHERE, size, V(0, 0, 5), V(0, 0, 1)), -1.0);
  EXPECT_EQ(curvedDepth(mjGEOM_SPHERE, size, V(0, 0, -5), V(0, 0, 0)), -1.0);  // degenerate ray
}

TEST(CurvedDepth, CapsuleEndCapAndSide) {
  const double size[3] = {0.5, 1.0, 0};  // radius, half-length
  EXPECT_NEAR(curvedDepth(mjGEOM_CAPSULE, size, V(0, 0, -5), V(0, 0, 1)), 3.5, kTol);
  EXPECT_NEAR(curvedDepth(mjGEOM_CAPSULE, size, V(-5, 0, 0.3), V(1, 0, 0)), 4.5, kTol);
  // Beside the cylinder part's end, within the end sphere: sqrt(0.25 - 0.2^2) from the axis.
  EXPECT_NEAR(curvedDepth(mjGEOM_CAPSULE, size, V(-5, 0, 1.2), V(1, 0, 0)), 5.0 - std::sqrt(0.21), kTol);
  EXPECT_EQ(curvedDepth(mjGEOM_CAPSULE, size, V(-5, 0, 1.6), V(1, 0, 0)), -1.0);
}

TEST(CurvedDepth, CylinderFlatCapsAndSide) {
  const double size[3] = {0.5, 1.0, 0};
  EXPECT_NEAR(curvedDepth(mjGEOM_CYLINDER, size, V(0, 0, -5), V(0, 0, 1)), 4.0, kTol);
  EXPECT_NEAR(curvedDepth(mjGEOM_CYLINDER, size, V(0.2, 0, 5), V(0, 0, -1)), 4.0, kTol);
  EXPECT_NEAR(curvedDepth(mjGEOM_CYLINDER, size, V(-5, 0, 0.3), V(1, 0, 0)), 4.5, kTol);
  // Past the flat end there is nothing (unlike a capsule).
  EXPECT_EQ(curvedDepth(mjGEOM_CYLINDER, size, V(-5, 0, 1.2), V(1, 0, 0)), -1.0);
  // Down the axis outside the radius: misses both caps and the side.
  EXPECT_EQ(curvedDepth(mjGEOM_CYLINDER, size, V(0.6, 0, -5), V(0, 0, 1)), -1.0);
}

TEST(CurvedDepth, EllipsoidAlongEachAxisAndAsMuJoCoSeesIt) {
  const double size[3] = {1.0, 2.0, 0.5};
  EXPECT_NEAR(curvedDepth(mjGEOM_ELLIPSOID, size, V(-5, 0, 0), V(1, 0, 0)), 4.0, kTol);
  EXPECT_NEAR(curvedDepth(mjGEOM_ELLIPSOID, size, V(0, -5, 0), V(0, 1, 0)), 3.0, kTol);
  EXPECT_NEAR(curvedDepth(mjGEOM_ELLIPSOID, size, V(0, 0, -5), V(0, 0, 2)), 2.25, kTol);
  EXPECT_NEAR(curvedDepth(mjGEOM_ELLIPSOID, size, V(0, 0, 0), V(1, 0, 0)), 1.0, kTol);  // from inside
  EXPECT_EQ(curvedDepth(mjGEOM_ELLIPSOID, size, V(1.1, 0, -5), V(0, 0, 1)), -1.0);
  // Oblique rays against mju_rayGeom (the ellipsoid at the origin, unrotated; its t along the unit ray).
  const mjtNum pos[3] = {0, 0, 0}, mat[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    const V o(-3.0 + 0.013 * i, 2.5 - 0.021 * i, -4.0 + 0.007 * i), d = (V(0.1, -0.05, 0.0) - o) / 3.0;
    const double t = curvedDepth(mjGEOM_ELLIPSOID, size, o, d + V(0.001 * (i % 7), -0.002 * (i % 5), 0.0));
    const V dir = d + V(0.001 * (i % 7), -0.002 * (i % 5), 0.0);
    const mjtNum pnt[3] = {o.x(), o.y(), o.z()},
                 vec[3] = {dir.x() / dir.norm(), dir.y() / dir.norm(), dir.z() / dir.norm()};
    const double mj = mju_rayGeom(pos, mat, size, pnt, vec, mjGEOM_ELLIPSOID);
    if (mj < 0.0) {
      EXPECT_EQ(t, -1.0) << i;
    } else {
      EXPECT_NEAR(t * dir.norm(), mj, 1e-9) << i;
      ++hits;
    }
  }
  EXPECT_GT(hits, 100);
}

TEST(CurvedDepth, OtherTypesAreLeftToMuJoCo) {
  const double size[3] = {1.0, 1.0, 1.0};
  EXPECT_EQ(curvedDepth(mjGEOM_BOX, size, V(0, 0, -5), V(0, 0, 1)), -2.0);
}

}  // namespace
