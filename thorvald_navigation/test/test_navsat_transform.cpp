// NavsatTransform: the datum from a parameter and from the first fix (IMU heading, robot pose), declination and
// yaw offset, altitude, the covariance's rotation, the way back to latitude and longitude.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "thorvald_navigation/navsat_transform.h"

namespace tn = thorvald_navigation;

namespace {

// On zone 31's central meridian: no grid convergence, so grid and true north agree.
constexpr double kLat = 52.0, kLon = 3.0;

/// The fix `east`, `north` metres from (lat, lon) in the UTM grid, through the inverse projection.
tn::GeoFix offset(double lat, double lon, double east, double north) {
  tn::UtmPoint u = *tn::toUtm(lat, lon);
  u.easting += east;
  u.northing += north;
  const tn::LatLon ll = *tn::fromUtm(u);
  tn::GeoFix f;
  f.lat_deg = ll.lat_deg;
  f.lon_deg = ll.lon_deg;
  return f;
}

}  // namespace

TEST(NavsatTransform, NothingBeforeTheDatum) {
  tn::NavsatTransform t;
  EXPECT_FALSE(t.ready());
  EXPECT_FALSE(t.toWorld(offset(kLat, kLon, 0, 0)));
  EXPECT_FALSE(t.toLatLon(0, 0));
  EXPECT_NE(t.setDatum(86.0, 0.0, 0.0, 0.0), "");  // outside UTM
  EXPECT_FALSE(t.ready());
}

TEST(NavsatTransform, DatumParameterPutsTheOriginThere) {
  tn::NavsatTransform t;
  ASSERT_EQ(t.setDatum(kLat, kLon, 0.0, 0.0), "");  // world x = east
  const auto origin = t.toWorld(offset(kLat, kLon, 0, 0));
  ASSERT_TRUE(origin);
  EXPECT_NEAR(origin->position.norm(), 0.0, 1e-6);
  const auto p = t.toWorld(offset(kLat, kLon, 3.0, 10.0));
  EXPECT_NEAR(p->position.x(), 3.0, 1e-6);
  EXPECT_NEAR(p->position.y(), 10.0, 1e-6);
  // World x pointing north: a point 10 m north is straight ahead.
  tn::NavsatTransform north;
  ASSERT_EQ(north.setDatum(kLat, kLon, 0.0, M_PI / 2), "");
  const auto q = north.toWorld(offset(kLat, kLon, 0.0, 10.0));
  EXPECT_NEAR(q->position.x(), 10.0, 1e-6);
  EXPECT_NEAR(q->position.y(), 0.0, 1e-6);
}

TEST(NavsatTransform, FirstFixWithHeadingAndRobotPose) {
  tn::NavsatOptions o;
  o.magnetic_declination_rad = 0.1;
  o.yaw_offset_rad = M_PI / 2;  // the IMU reads 0 facing north
  tn::NavsatTransform t(o);
  EXPECT_NEAR(t.headingEnu(0.2), 0.2 + 0.1 + M_PI / 2, 1e-12);
  // The robot is at (2, 3) with world yaw 0.5 when the first fix comes; its true heading is 30 deg east of north.
  const double heading_enu = M_PI / 2 - M_PI / 6;
  const tn::WorldPose robot{2.0, 3.0, 0.0, 0.5};
  ASSERT_EQ(t.setFromFix(offset(kLat, kLon, 0, 0), heading_enu - 0.1 - M_PI / 2, robot), "");
  const auto at_datum = t.toWorld(offset(kLat, kLon, 0, 0));
  EXPECT_NEAR(at_datum->position.x(), 2.0, 1e-6);
  EXPECT_NEAR(at_datum->position.y(), 3.0, 1e-6);
  // 10 m straight ahead along the true heading is 10 m along the world yaw.
  const auto ahead = t.toWorld(offset(kLat, kLon, 10.0 * std::cos(heading_enu), 10.0 * std::sin(heading_enu)));
  EXPECT_NEAR(ahead->position.x(), 2.0 + 10.0 * std::cos(0.5), 1e-6);
  EXPECT_NEAR(ahead->position.y(), 3.0 + 10.0 * std::sin(0.5), 1e-6);
  // And back to latitude and longitude.
  const auto ll = t.toLatLon(ahead->position.x(), ahead->position.y());
  const tn::GeoFix f = offset(kLat, kLon, 10.0 * std::cos(heading_enu), 10.0 * std::sin(heading_enu));
  EXPECT_NEAR(ll->lat_deg, f.lat_deg, 1e-9);
  EXPECT_NEAR(ll->lon_deg, f.lon_deg, 1e-9);
}

TEST(NavsatTransform, FirstFixVersusParameterGiveTheSameWorld) {
  // A datum parameter is the first fix of a robot standing at the world origin with its heading.
  tn::NavsatTransform by_param, by_fix;
  ASSERT_EQ(by_param.setDatum(kLat, kLon, 0.0, 0.7), "");
  ASSERT_EQ(by_fix.setFromFix(offset(kLat, kLon, 0, 0), 0.7, tn::WorldPose{}), "");
  const tn::GeoFix f = offset(kLat, kLon, -12.0, 25.0);
  EXPECT_NEAR((by_param.toWorld(f)->position - by_fix.toWorld(f)->position).norm(), 0.0, 1e-9);
}

TEST(NavsatTransform, ConvergenceOffTheCentralMeridian) {
  // 2 deg east of zone 31's meridian: a point due true-north of the datum is still straight ahead in a world
  // whose x axis was set to true north.
  const double lon = 5.0;
  tn::NavsatTransform t;
  ASSERT_EQ(t.setFromFix(
                [&] {
                  tn::GeoFix g;
                  g.lat_deg = kLat;
                  g.lon_deg = lon;
                  return g;
                }(),
                M_PI / 2, tn::WorldPose{}),
            "");
  tn::GeoFix north;
  north.lat_deg = kLat + 100.0 / 111250.0;  // ~100 m along the meridian
  north.lon_deg = lon;
  const auto p = t.toWorld(north);
  EXPECT_NEAR(p->position.y(), 0.0, 0.01);
  EXPECT_NEAR(p->position.x(), 100.0, 0.5);
}

TEST(NavsatTransform, AltitudeAndCovariance) {
  tn::NavsatTransform t;
  ASSERT_EQ(t.setFromFix(
                [] {
                  tn::GeoFix g = offset(kLat, kLon, 0, 0);
                  g.alt_m = 100.0;
                  return g;
                }(),
                M_PI / 2, tn::WorldPose{0, 0, 0.5, 0.0}),
            "");  // world x = north
  tn::GeoFix f = offset(kLat, kLon, 0, 0);
  f.alt_m = 101.0;
  f.covariance_enu = Eigen::Vector3d(4.0, 1.0, 9.0).asDiagonal();
  const auto w = t.toWorld(f);
  EXPECT_NEAR(w->position.z(), 1.5, 1e-9);
  EXPECT_NEAR(w->covariance(0, 0), 1.0, 1e-9);  // world x is north
  EXPECT_NEAR(w->covariance(1, 1), 4.0, 1e-9);
  EXPECT_NEAR(w->covariance(2, 2), 9.0, 1e-9);
  tn::NavsatOptions o;
  o.zero_altitude = true;
  tn::NavsatTransform flat(o);
  ASSERT_EQ(flat.setDatum(kLat, kLon, 100.0, 0.0), "");
  EXPECT_EQ(flat.toWorld(f)->position.z(), 0.0);
}

TEST(NavsatTransform, UtmFrameInTheWorld) {
  tn::NavsatTransform t;
  ASSERT_EQ(t.setDatum(kLat, kLon, 0.0, M_PI / 2), "");
  const auto g = t.utmInWorld();
  ASSERT_TRUE(g);
  // The datum's grid point, carried by the utm -> world transform, lands on the origin.
  const tn::UtmPoint d = t.datumUtm();
  const double c = std::cos(g->yaw), s = std::sin(g->yaw);
  EXPECT_NEAR(g->x + c * d.easting - s * d.northing, 0.0, 1e-6);
  EXPECT_NEAR(g->y + s * d.easting + c * d.northing, 0.0, 1e-6);
  EXPECT_EQ(d.zone, 31);
}

TEST(NavsatTransform, DatumOnlyFromAGoodEnoughFix) {
  tn::GeoFix rtk = offset(kLat, kLon, 0, 0);
  rtk.covariance_enu = Eigen::Vector3d(1e-4, 1e-4, 4e-4).asDiagonal();  // RTK fixed: 1 cm
  EXPECT_EQ(tn::horizontalSigma(rtk), 0.01);
  EXPECT_EQ(tn::datumFixRefusal(rtk, tn::kDatumMaxSigmaM), "");
  tn::GeoFix single = rtk;
  single.covariance_enu = Eigen::Vector3d(2.25, 1.0, 6.25).asDiagonal();  // single: 1.5 m east
  EXPECT_NEAR(tn::horizontalSigma(single), 1.5, 1e-12);
  EXPECT_NE(tn::datumFixRefusal(single, tn::kDatumMaxSigmaM).find("1.5 m"), std::string::npos);
  tn::GeoFix flt = rtk;
  flt.covariance_enu(1, 1) = 0.09;  // float: 0.3 m north
  EXPECT_NE(tn::datumFixRefusal(flt, tn::kDatumMaxSigmaM), "");
  EXPECT_EQ(tn::datumFixRefusal(flt, 0.5), "");
  tn::GeoFix unknown = rtk;
  unknown.covariance_enu(0, 0) = std::nan("");
  EXPECT_TRUE(std::isinf(tn::horizontalSigma(unknown)));
  EXPECT_NE(tn::datumFixRefusal(unknown, 1e9), "");
  // infinity: any fix, even one without a covariance (robot_localization takes the first fix).
  EXPECT_EQ(tn::datumFixRefusal(single, std::numeric_limits<double>::infinity()), "");
  EXPECT_EQ(tn::datumFixRefusal(unknown, std::numeric_limits<double>::infinity()), "");
}

namespace {

/// base_link's orientation: yaw, then pitch, then roll (ZYX).
Eigen::Quaterniond rpy(double roll, double pitch, double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

}  // namespace

TEST(NavsatTransform, AntennaOnATiltedMastMovedToBaseLink) {
  // The cotton rover's mast: the antenna 2.46 m up, a little behind and left of base_link.
  const Eigen::Vector3d mount(-0.30, 0.20, 2.46);
  // Level, facing north: the offset is the mount turned by 90 deg.
  const Eigen::Vector3d level = tn::antennaOffsetInWorld(mount, rpy(0, 0, M_PI / 2));
  EXPECT_NEAR(level.x(), -0.20, 1e-12);
  EXPECT_NEAR(level.y(), -0.30, 1e-12);
  EXPECT_NEAR(level.z(), 2.46, 1e-12);
  // Rolled 5 deg to the right (about x, facing east): the mast's top goes 2.46 sin 5 deg = 0.214 m south.
  const Eigen::Vector3d rolled = tn::antennaOffsetInWorld(mount, rpy(0.0873, 0.0, 0.0));
  EXPECT_NEAR(rolled.y(), 0.20 * std::cos(0.0873) - 2.46 * std::sin(0.0873), 1e-9);
  EXPECT_LT(rolled.y(), -0.01);

  // World x = east at the datum (parameter). base_link at (5, 2, 0) tilted (roll 0.08, pitch -0.06, yaw 0.7): the
  // fix is the antenna's; moved by the offset it is base_link's, to the millimetre.
  tn::NavsatTransform t;
  ASSERT_EQ(t.setDatum(kLat, kLon, 0.0, 0.0), "");
  const Eigen::Quaterniond q = rpy(0.08, -0.06, 0.7);
  const Eigen::Vector3d base(5.0, 2.0, 0.0);
  const Eigen::Vector3d antenna = base + q * mount;
  tn::GeoFix f = offset(kLat, kLon, antenna.x(), antenna.y());
  f.alt_m = antenna.z();
  const auto w = t.toWorld(f, tn::antennaOffsetInWorld(mount, q));
  ASSERT_TRUE(w);
  EXPECT_NEAR(w->position.x(), base.x(), 1e-6);
  EXPECT_NEAR(w->position.y(), base.y(), 1e-6);
  EXPECT_NEAR(w->position.z(), base.z(), 1e-6);
  // Without the offset the fix is the antenna's, 0.3 m and more from base_link: the offset is what moved it.
  EXPECT_GT((t.toWorld(f)->position.head<2>() - base.head<2>()).norm(), 0.3);
}

TEST(NavsatTransform, DatumFromAnAntennaFixIsBaseLinks) {
  // The datum fix comes from the antenna of a robot standing tilted at (1, -2) with world yaw 0 facing east; later
  // the robot, tilted the other way, is at (4, 1) facing north. Both positions come back as base_link's.
  const Eigen::Vector3d mount(0.1, -0.15, 2.46);
  const Eigen::Vector3d base0(1.0, -2.0, 0.0), base1(4.0, 1.0, 0.0);
  const Eigen::Quaterniond q0 = rpy(-0.05, 0.04, 0.0), q1 = rpy(0.06, 0.03, M_PI / 2);
  // The world frame's origin and axes are the grid's at the datum shifted by where the robot stood: east = x.
  const Eigen::Vector3d a0 = base0 + q0 * mount, a1 = base1 + q1 * mount;
  tn::NavsatTransform t;
  ASSERT_EQ(t.setFromFix(offset(kLat, kLon, 0, 0), 0.0, tn::WorldPose{base0.x(), base0.y(), 0.0, 0.0},
                         tn::antennaOffsetInWorld(mount, q0)),
            "");
  const auto w0 = t.toWorld(offset(kLat, kLon, 0, 0), tn::antennaOffsetInWorld(mount, q0));
  EXPECT_NEAR((w0->position.head<2>() - base0.head<2>()).norm(), 0.0, 1e-6);
  const auto w1 = t.toWorld(offset(kLat, kLon, a1.x() - a0.x(), a1.y() - a0.y()), tn::antennaOffsetInWorld(mount, q1));
  EXPECT_NEAR(w1->position.x(), base1.x(), 1e-6);
  EXPECT_NEAR(w1->position.y(), base1.y(), 1e-6);
}
