// Pure pursuit and the row-end turn on the rover's own models: the hydrostatic drive (swashplate deadband, flow lag,
// articulation moved by two relays at its rate) under the deadband-aware speed control and the articulation P
// controller, with the front axle's pose integrated as ArticulatedOdometry does.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cotton_harvester/control/articulation_controller.h"
#include "cotton_harvester/control/deadband_position_controller.h"
#include "cotton_harvester/control/hydrostatic_drive_model.h"
#include "cotton_harvester/control/pure_pursuit.h"
#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester/control/row_turn_planner.h"

namespace cc = cotton_harvester::control;

namespace {

constexpr double kRowSpacing = 0.9144;  // paper: rows 36 in apart
constexpr double kHarvestSpeed = 0.25;  // RoverControllerParams::max_speed_mps

/// The rover on its models, closed through pure pursuit.
class RoverLoop {
 public:
  RoverLoop(const cc::Pose2& start, double speed_mps) : speed_mps_(speed_mps), odometry_(0.91) {
    x0_ = start;
    deadband_.setVelocity(speed_mps);
  }
  /// The pose pure pursuit is given reports this much less heading than the rover has [rad] (position true).
  void setHeadingBias(double bias_rad) { heading_bias_rad_ = bias_rad; }
  /// Runs until the path is done or `max_s` simulated seconds; records the cross-track after `settle_m` of travel.
  void follow(cc::PurePursuit* pursuit, double max_s, double settle_m = 0.0) {
    const double dt = 0.02;
    for (double t = 0.0; t < max_s; t += dt) {
      cc::Pose2 pose = this->pose();
      pose.yaw -= heading_bias_rad_;
      const cc::PursuitStep step = pursuit->update(pose, drive_.speedMps());
      last_ = step;
      if (step.finished) return;
      if (drive_.positionM() >= settle_m) {
        sum_sq_ += step.cross_track_m * step.cross_track_m;
        ++samples_;
        max_abs_ = std::max(max_abs_, std::abs(step.cross_track_m));
      }
      const cc::RelayCommand relays = articulation_.update(step.articulation_deg, drive_.articulationDeg(), dt);
      const double before = drive_.positionM();
      drive_.step(deadband_.update(drive_.positionM(), dt), relays.left, relays.right, dt);
      odometry_.update(drive_.positionM() - before, drive_.articulationDeg(), dt);
    }
  }
  cc::Pose2 pose() const {
    const double c = std::cos(x0_.yaw), s = std::sin(x0_.yaw);
    return {x0_.x + c * odometry_.x() - s * odometry_.y(), x0_.y + s * odometry_.x() + c * odometry_.y(),
            cc::wrapAngle(x0_.yaw + odometry_.yaw())};
  }
  double rms() const { return samples_ ? std::sqrt(sum_sq_ / samples_) : 0.0; }
  double maxAbs() const { return max_abs_; }
  const cc::PursuitStep& last() const { return last_; }
  double travelled() const { return drive_.positionM(); }

 private:
  double speed_mps_;
  double heading_bias_rad_ = 0.0;
  cc::Pose2 x0_;
  cc::HydrostaticDriveModel drive_;
  cc::DeadbandPositionController deadband_;
  cc::ArticulationController articulation_;
  cc::ArticulatedOdometry odometry_;
  cc::PursuitStep last_;
  double sum_sq_ = 0.0, max_abs_ = 0.0;
  int samples_ = 0;
};

cc::WaypointPath straightRow(double length_m) { return cc::WaypointPath({{0.0, 0.0}, {length_m, 0.0}}); }

}  // namespace

TEST(RoverKinematics, ArticulationAndCurvatureAreInverse) {
  // 45 deg on 0.91 m halves: R = 0.91 / tan(22.5 deg) = 2.1969 m.
  EXPECT_NEAR(cc::minTurnRadius(45.0, 0.91), 0.91 / std::tan(M_PI / 8.0), 1e-9);
  EXPECT_NEAR(cc::minTurnRadius(45.0, 0.91), 2.1969, 1e-4);
  for (double deg : {-40.0, -10.0, 0.0, 5.0, 30.0})
    EXPECT_NEAR(cc::articulationForCurvature(cc::curvatureForArticulation(deg, 0.91), 0.91), deg, 1e-9);
}

TEST(PurePursuit, LookaheadGrowsWithSpeedWithinItsLimits) {
  cc::PurePursuitParams p;
  p.lookahead_m = 0.5;
  p.lookahead_per_mps = 2.0;
  p.min_lookahead_m = 0.8;
  p.max_lookahead_m = 2.0;
  cc::PurePursuit pursuit(p);
  EXPECT_DOUBLE_EQ(pursuit.lookahead(0.0), 0.8);   // 0.5 below the minimum
  EXPECT_DOUBLE_EQ(pursuit.lookahead(0.25), 1.0);  // 0.5 + 2 * 0.25
  EXPECT_DOUBLE_EQ(pursuit.lookahead(-0.25), 1.0);
  EXPECT_DOUBLE_EQ(pursuit.lookahead(5.0), 2.0);  // capped
  p.max_lookahead_m = 0.5;
  EXPECT_EQ(p.check(), "max_lookahead_m: expected >= min_lookahead_m");
  EXPECT_THROW(cc::PurePursuit{p}, std::invalid_argument);
}

TEST(PurePursuit, SetPointStaysWithinTheArticulationLimit) {
  cc::PurePursuit pursuit;
  pursuit.setPath(straightRow(10.0));
  // Rover beside the row, facing away from it: the full articulation towards the path, never more.
  const cc::PursuitStep step = pursuit.update({1.0, 0.5, M_PI_2}, 0.0);
  EXPECT_LT(step.curvature_1pm, -1.0);  // asks for more than the rover can turn
  EXPECT_DOUBLE_EQ(step.articulation_deg, -45.0);
  EXPECT_NEAR(step.cross_track_m, 0.5, 1e-9);
  EXPECT_FALSE(step.finished);
  // On the path and aligned: straight.
  EXPECT_NEAR(pursuit.update({2.0, 0.0, 0.0}, 0.25).articulation_deg, 0.0, 1e-9);
}

TEST(PurePursuit, GoalOnTheCircleGivesItsCurvature) {
  // The goal point one lookahead along a straight path from a rover 0.3 m right of it: kappa = 2 y / d^2.
  cc::PurePursuitParams p;
  p.lookahead_per_mps = 0.0;
  p.lookahead_m = 1.5;
  cc::PurePursuit pursuit(p);
  pursuit.setPath(straightRow(10.0));
  const cc::PursuitStep step = pursuit.update({3.0, -0.3, 0.0}, 0.0);
  const double kappa = 2.0 * 0.3 / (1.5 * 1.5 + 0.3 * 0.3);
  EXPECT_NEAR(step.curvature_1pm, kappa, 1e-9);
  EXPECT_NEAR(step.articulation_deg, 2.0 * std::atan(0.91 * kappa) * 180.0 / M_PI, 1e-9);
}

TEST(PurePursuit, StraightRowCrossTrackConverges) {
  cc::PurePursuit pursuit;
  pursuit.setPath(straightRow(20.0));
  RoverLoop rover({0.0, 0.15, 0.05}, kHarvestSpeed);  // 15 cm off, 3 deg off the row
  rover.follow(&pursuit, 200.0, 6.0);
  EXPECT_TRUE(rover.last().finished);
  EXPECT_LT(rover.maxAbs(), 0.02);  // after 6 m: within 2 cm
  EXPECT_LT(rover.rms(), 0.01);
  EXPECT_GT(rover.travelled(), 19.9);
}

TEST(PurePursuit, OffsetStartReachesTheRowWithoutOvershoot) {
  cc::PurePursuit pursuit;
  pursuit.setPath(straightRow(25.0));
  RoverLoop rover({0.0, -1.0, 0.0}, kHarvestSpeed);  // a metre right of the row
  double worst_left = 0.0;
  for (int i = 0; i < 50 && !rover.last().finished; ++i) {
    rover.follow(&pursuit, 2.0);
    worst_left = std::max(worst_left, rover.last().cross_track_m);
  }
  EXPECT_LT(worst_left, 0.10);  // crosses the row by less than 10 cm
  RoverLoop settled({0.0, -1.0, 0.0}, kHarvestSpeed);
  cc::PurePursuit again;
  again.setPath(straightRow(25.0));
  settled.follow(&again, 300.0, 12.0);
  EXPECT_LT(settled.maxAbs(), 0.03);
}

TEST(PurePursuit, HeadingCorrectionRemovesTheOffsetOfABiasedHeading) {
  // The pose's heading 2.6 deg short of the rover's (a fused yaw that drifted in a turn), its position true: without
  // the correction the rover holds lookahead * tan(2.6 deg) = 7.7 cm beside the row; with it, it converges.
  const double bias = 2.6 * M_PI / 180.0;
  cc::PurePursuit plain;
  plain.setPath(straightRow(20.0));
  RoverLoop biased({0.0, 0.0, 0.0}, kHarvestSpeed);
  biased.setHeadingBias(bias);
  biased.follow(&plain, 200.0, 10.0);
  ASSERT_TRUE(biased.last().finished);
  EXPECT_GT(biased.rms(), 0.06);
  EXPECT_DOUBLE_EQ(biased.last().heading_correction_rad, 0.0);

  cc::PurePursuitParams p;
  p.heading_correction_gain = 0.2;
  cc::PurePursuit corrected(p);
  corrected.setPath(straightRow(20.0));
  RoverLoop rover({0.0, 0.0, 0.0}, kHarvestSpeed);
  rover.setHeadingBias(bias);
  rover.follow(&corrected, 200.0, 10.0);
  ASSERT_TRUE(rover.last().finished);
  EXPECT_LT(rover.maxAbs(), 0.02);  // the second half of the row: within 2 cm
  EXPECT_NEAR(rover.last().heading_correction_rad, bias, 0.5 * M_PI / 180.0);
  // Kept on the next path, within its limit.
  corrected.setPath(straightRow(20.0));
  EXPECT_NEAR(corrected.update({0.0, 0.0, 0.0}, 0.0).heading_correction_rad, rover.last().heading_correction_rad, 1e-9);
  p.heading_correction_gain = -0.1;
  EXPECT_EQ(p.check(), "heading_correction_gain: expected >= 0");
}

TEST(PurePursuit, HeadingCorrectionIgnoresCurves) {
  // On an arc the cross-track is the tracking's lag: the correction does not move.
  cc::PurePursuitParams p;
  p.heading_correction_gain = 0.2;
  cc::PurePursuit pursuit(p);
  std::vector<Eigen::Vector2d> arc;
  for (int i = 0; i <= 60; ++i) arc.emplace_back(3.0 * std::sin(i * 0.05), 3.0 - 3.0 * std::cos(i * 0.05));
  pursuit.setPath(cc::WaypointPath(arc));
  for (int i = 0; i < 50; ++i)
    EXPECT_DOUBLE_EQ(pursuit.update({0.02 * i, -0.1, 0.0}, 0.25).heading_correction_rad, 0.0);
}

TEST(PurePursuit, HeadingCorrectionWaitsUntilTheRoverIsSettled) {
  // 0.3 m beside a straight row (a turn's exit): pure pursuit asks far more than 2 deg, so the cross-track is lag, not
  // a heading error, and the correction does not move; close to the row and straight, it does.
  cc::PurePursuitParams p;
  p.heading_correction_gain = 0.2;
  cc::PurePursuit pursuit(p);
  pursuit.setPath(straightRow(20.0));
  for (int i = 0; i < 20; ++i) EXPECT_DOUBLE_EQ(pursuit.update({0.02 * i, 0.3, 0.0}, 0.25).heading_correction_rad, 0.0);
  pursuit.resetHeadingCorrection();
  for (int i = 0; i < 20; ++i) pursuit.update({1.0 + 0.02 * i, 0.005, 0.0}, 0.25);
  EXPECT_GT(pursuit.update({1.4, 0.005, 0.0}, 0.25).heading_correction_rad, 0.0);
}

TEST(PurePursuit, CurvedPathIsFollowed) {
  // A quarter circle of 8 m radius after 3 m straight, 2 m straight after it.
  std::vector<Eigen::Vector2d> pts{{0.0, 0.0}, {3.0, 0.0}};
  const double r = 8.0;
  for (int i = 1; i <= 60; ++i) {
    const double a = M_PI_2 * i / 60.0;
    pts.emplace_back(3.0 + r * std::sin(a), r - r * std::cos(a));
  }
  pts.emplace_back(3.0 + r, r + 2.0);
  cc::PurePursuit pursuit;
  pursuit.setPath(cc::WaypointPath(pts));
  RoverLoop rover({0.0, 0.0, 0.0}, kHarvestSpeed);
  rover.follow(&pursuit, 300.0);
  EXPECT_TRUE(rover.last().finished);
  // Pure pursuit cuts a curve by about L^2 / (2 R) on the inside: 1.7^2 / 16 = 0.18 m at most; lag of the relays adds.
  EXPECT_LT(rover.maxAbs(), 0.20);
  EXPECT_NEAR(rover.pose().yaw, M_PI_2, 0.05);
}

TEST(PurePursuit, NeverTakesTheNeighbouringLegForThePath) {
  // Out along y = 0 and back along y = 0.9144: beside the far end of the return leg, the projection still follows
  // progress on the first leg.
  cc::PurePursuit pursuit;
  pursuit.setPath(cc::WaypointPath({{0.0, 0.0}, {10.0, 0.0}, {10.0, kRowSpacing}, {0.0, kRowSpacing}}));
  const cc::PursuitStep step = pursuit.update({0.5, 0.8, 0.0}, 0.0);
  EXPECT_LT(step.s_m, 1.0);
  EXPECT_NEAR(step.cross_track_m, 0.8, 1e-9);
}

TEST(PurePursuit, OmegaTurnEntersTheNextRowAligned) {
  // 10 m of row, the omega turn at R = 2.5 m (the rover can do 2.2) at turning speed, 8 m of the next row back.
  cc::RowTurnParams turn_params;
  turn_params.turn_radius_m = 2.5;
  const cc::RowTurn turn = cc::planRowTurn({10.0, 0.0}, 0.0, kRowSpacing, turn_params);
  std::vector<Eigen::Vector2d> pts{{0.0, 0.0}};
  pts.insert(pts.end(), turn.waypoints.begin(), turn.waypoints.end());
  pts.emplace_back(2.0, kRowSpacing);
  cc::PurePursuit pursuit;
  pursuit.setPath(cc::WaypointPath(pts));
  RoverLoop rover({0.0, 0.0, 0.0}, 0.15);
  double deepest = 0.0, widest = 0.0;
  while (!rover.last().finished && rover.travelled() < 60.0) {
    rover.follow(&pursuit, 0.5);
    deepest = std::max(deepest, rover.pose().x);
    widest = std::max(widest, std::abs(rover.pose().y - 0.5 * kRowSpacing));
  }
  ASSERT_TRUE(rover.last().finished);
  // In the next row (from 2 m before its end on): on its line within 5 cm and 3 deg.
  EXPECT_NEAR(rover.pose().y, kRowSpacing, 0.05);
  EXPECT_NEAR(std::abs(cc::wrapAngle(rover.pose().yaw)), M_PI, 3.0 * M_PI / 180.0);
  // The turn stays within the planned room and 0.3 m of it.
  EXPECT_LT(deepest, 10.0 + turn.depth_m + 0.3);
  EXPECT_LT(widest, 0.5 * (turn.max_lateral_m - turn.min_lateral_m) + 0.3);
}

TEST(RoverKinematics, ArticulatingInPlaceSwingsTheFrontHalf) {
  // Both axles roll without sliding sideways: the front half turns by the integral of dgamma / (1 + cos gamma),
  // tan(gamma / 2) from straight; back to straight, it is where it started.
  cc::ArticulatedOdometry odometry(0.91);
  for (int i = 0; i <= 400; ++i) odometry.update(0.0, 0.1 * i, 0.02);
  EXPECT_NEAR(odometry.yaw(), std::tan(20.0 * M_PI / 180.0), 1e-4);
  for (int i = 400; i >= 0; --i) odometry.update(0.0, 0.1 * i, 0.02);
  EXPECT_NEAR(odometry.yaw(), 0.0, 1e-9);
  EXPECT_NEAR(odometry.x(), 0.0, 1e-12);
}
