#include <gtest/gtest.h>

#include "thorvald_model/rigid_body.h"

using thorvald_model::combine;
using thorvald_model::MassProperties;
using thorvald_model::placed;
using thorvald_model::solidBox;
using thorvald_model::solidCylinder;
using thorvald_model::tube;

constexpr double kTol = 1e-12;

TEST(RigidBody, BoxInertiaIsTheTextbookFormula) {
  const MassProperties b = solidBox({0.2, 0.4, 0.6}, 3.0);
  EXPECT_NEAR(b.inertia(0, 0), 3.0 / 12.0 * (0.16 + 0.36), kTol);
  EXPECT_NEAR(b.inertia(1, 1), 3.0 / 12.0 * (0.04 + 0.36), kTol);
  EXPECT_NEAR(b.inertia(2, 2), 3.0 / 12.0 * (0.04 + 0.16), kTol);
  EXPECT_NEAR(b.inertia(0, 1), 0.0, kTol);
}

TEST(RigidBody, CylinderTurnedOntoYHasItsPolarMomentAboutY) {
  const double pi = 3.14159265358979323846;
  const MassProperties c = solidCylinder(0.2, 0.16, 4.0);
  EXPECT_NEAR(c.inertia(2, 2), 0.5 * 4.0 * 0.04, kTol);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const MassProperties turned = placed(c, {1, 2, 3}, r);
  EXPECT_NEAR(turned.inertia(1, 1), 0.5 * 4.0 * 0.04, 1e-12);
  EXPECT_NEAR(turned.inertia(2, 2), 4.0 / 12.0 * (3 * 0.04 + 0.0256), 1e-12);
  EXPECT_TRUE(turned.com_m.isApprox(Eigen::Vector3d(1, 2, 3)));
}

TEST(RigidBody, TubeIsLighterInTheMiddle) {
  const MassProperties t = tube(0.024, 0.021, 1.0, 1.0);
  EXPECT_NEAR(t.inertia(2, 2), 0.5 * (0.024 * 0.024 + 0.021 * 0.021), kTol);
}

TEST(RigidBody, CombineUsesTheParallelAxisTheorem) {
  const MassProperties a = placed(solidBox({0.1, 0.1, 0.1}, 2.0), {-1, 0, 0});
  const MassProperties b = placed(solidBox({0.1, 0.1, 0.1}, 2.0), {1, 0, 0});
  const MassProperties s = combine({a, b});
  const double own = 2.0 / 12.0 * 0.02;
  EXPECT_NEAR(s.mass_kg, 4.0, kTol);
  EXPECT_NEAR(s.com_m.norm(), 0.0, kTol);
  EXPECT_NEAR(s.inertia(0, 0), 2 * own, kTol);
  EXPECT_NEAR(s.inertia(1, 1), 2 * (own + 2.0 * 1.0), kTol);
  EXPECT_NEAR(s.inertia(2, 2), 2 * (own + 2.0 * 1.0), kTol);
}

TEST(RigidBody, CombineOffDiagonalProductsOfInertia) {
  // Two point-like masses at (1, 1, 0) and (-1, -1, 0): Ixy = -sum m x y = -2 m.
  const MassProperties a = placed(solidBox({1e-6, 1e-6, 1e-6}, 1.0), {1, 1, 0});
  const MassProperties b = placed(solidBox({1e-6, 1e-6, 1e-6}, 1.0), {-1, -1, 0});
  const MassProperties s = combine({a, b});
  EXPECT_NEAR(s.inertia(0, 1), -2.0, 1e-9);
  EXPECT_NEAR(s.inertia(2, 2), 4.0, 1e-9);
}

TEST(RigidBody, CombineOfNothingIsEmpty) { EXPECT_EQ(combine({}).mass_kg, 0.0); }
