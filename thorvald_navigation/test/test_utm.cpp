// UTM: against the meridian arc and the USGS (Snyder) series computed here independently, round trips, zones
// and bands at their edges, Norway and Svalbard, the southern hemisphere, a forced zone.
#include <cmath>

#include <gtest/gtest.h>

#include "thorvald_navigation/utm.h"

namespace tn = thorvald_navigation;

namespace {

constexpr double kDeg = M_PI / 180.0;

/// Snyder's series ("Map Projections: A Working Manual", USGS 1987, eqs. 8-9 to 8-10) for WGS84: a different
/// formulation from the library's Krueger series, good to millimetres within 3 deg of the central meridian.
std::pair<double, double> snyder(double lat_deg, double lon_deg, double lon0_deg) {
  const double a = 6378137.0, f = 1.0 / 298.257223563, k0 = 0.9996;
  const double e2 = f * (2 - f), e4 = e2 * e2, e6 = e4 * e2, ep2 = e2 / (1 - e2);
  const double phi = lat_deg * kDeg;
  const double n = a / std::sqrt(1 - e2 * std::sin(phi) * std::sin(phi));
  const double t = std::tan(phi) * std::tan(phi), c = ep2 * std::cos(phi) * std::cos(phi);
  const double aa = (lon_deg - lon0_deg) * kDeg * std::cos(phi);
  const double m = a * ((1 - e2 / 4 - 3 * e4 / 64 - 5 * e6 / 256) * phi -
                        (3 * e2 / 8 + 3 * e4 / 32 + 45 * e6 / 1024) * std::sin(2 * phi) +
                        (15 * e4 / 256 + 45 * e6 / 1024) * std::sin(4 * phi) - (35 * e6 / 3072) * std::sin(6 * phi));
  const double x =
      k0 * n *
      (aa + (1 - t + c) * std::pow(aa, 3) / 6 + (5 - 18 * t + t * t + 72 * c - 58 * ep2) * std::pow(aa, 5) / 120);
  const double y = k0 * (m + n * std::tan(phi) *
                                 (aa * aa / 2 + (5 - t + 9 * c + 4 * c * c) * std::pow(aa, 4) / 24 +
                                  (61 - 58 * t + t * t + 600 * c - 330 * ep2) * std::pow(aa, 6) / 720));
  return {500000.0 + x, lat_deg < 0 ? 1e7 + y : y};
}

}  // namespace

TEST(Utm, CentralMeridianAndMeridianArc) {
  const auto eq = tn::toUtm(0.0, 3.0);
  ASSERT_TRUE(eq);
  EXPECT_EQ(eq->zone, 31);
  EXPECT_NEAR(eq->easting, 500000.0, 1e-6);
  EXPECT_NEAR(eq->northing, 0.0, 1e-6);
  // WGS84's meridian arc from the equator to 45 deg is 4 984 944.378 m; UTM scales it by 0.9996.
  const auto mid = tn::toUtm(45.0, 9.0);
  ASSERT_TRUE(mid);
  EXPECT_EQ(mid->zone, 32);
  EXPECT_NEAR(mid->easting, 500000.0, 1e-6);
  EXPECT_NEAR(mid->northing, 0.9996 * 4984944.378, 0.002);
}

TEST(Utm, AgreesWithSnyderSeries) {
  // The cotton fields (Georgia, USA), Lincoln (UK), Aas (Norway), Cape Town, a point at a zone's edge.
  const double points[][2] = {{31.475, -83.528}, {53.228, -0.548}, {59.666, 10.768}, {-33.925, 18.424},
                              {40.0, -108.001},  {-45.0, 170.9},   {0.5, -0.5}};
  for (const auto& p : points) {
    const auto u = tn::toUtm(p[0], p[1]);
    ASSERT_TRUE(u);
    const auto [e, n] = snyder(p[0], p[1], tn::utmCentralMeridian(u->zone));
    EXPECT_NEAR(u->easting, e, 0.01) << p[0] << ", " << p[1];
    EXPECT_NEAR(u->northing, n, 0.01) << p[0] << ", " << p[1];
  }
}

TEST(Utm, RoundTripAcrossTheGlobe) {
  for (double lat = -79.5; lat <= 83.5; lat += 7.3) {
    for (double lon = -179.7; lon < 180.0; lon += 11.9) {
      const auto u = tn::toUtm(lat, lon);
      ASSERT_TRUE(u) << lat << ", " << lon;
      const auto back = tn::fromUtm(*u);
      ASSERT_TRUE(back);
      // 1e-9 deg is about 0.1 mm.
      EXPECT_NEAR(back->lat_deg, lat, 1e-9) << lat << ", " << lon;
      EXPECT_NEAR(back->lon_deg, lon, 1e-9) << lat << ", " << lon;
    }
  }
}

TEST(Utm, ZoneEdges) {
  EXPECT_EQ(*tn::utmZone(10.0, 5.999999), 31);
  EXPECT_EQ(*tn::utmZone(10.0, 6.0), 32);
  EXPECT_EQ(*tn::utmZone(10.0, -180.0), 1);
  EXPECT_EQ(*tn::utmZone(10.0, 180.0), 60);
  EXPECT_EQ(*tn::utmZone(10.0, 179.99), 60);
  EXPECT_EQ(*tn::utmZone(10.0, -0.0001), 30);
  EXPECT_EQ(*tn::utmZone(10.0, 0.0), 31);
  // South-west Norway is 32V; north of 64 deg it is not.
  EXPECT_EQ(*tn::utmZone(60.0, 5.0), 32);
  EXPECT_EQ(*tn::utmZone(60.0, 2.9), 31);
  EXPECT_EQ(*tn::utmZone(64.0, 5.0), 31);
  // Svalbard: 31X, 33X, 35X, 37X.
  EXPECT_EQ(*tn::utmZone(78.0, 8.9), 31);
  EXPECT_EQ(*tn::utmZone(78.0, 9.0), 33);
  EXPECT_EQ(*tn::utmZone(78.0, 20.9), 33);
  EXPECT_EQ(*tn::utmZone(78.0, 21.0), 35);
  EXPECT_EQ(*tn::utmZone(78.0, 41.9), 37);
  EXPECT_EQ(*tn::utmZone(78.0, 42.0), 38);
  EXPECT_FALSE(tn::utmZone(84.01, 0.0));
  EXPECT_FALSE(tn::utmZone(-80.01, 0.0));
  EXPECT_FALSE(tn::utmZone(NAN, 0.0));
  EXPECT_FALSE(tn::toUtm(85.0, 0.0));
}

TEST(Utm, Bands) {
  EXPECT_EQ(*tn::utmBand(-80.0), 'C');
  EXPECT_EQ(*tn::utmBand(-0.1), 'M');
  EXPECT_EQ(*tn::utmBand(0.0), 'N');
  EXPECT_EQ(*tn::utmBand(59.666), 'V');
  EXPECT_EQ(*tn::utmBand(72.0), 'X');
  EXPECT_EQ(*tn::utmBand(84.0), 'X');
  EXPECT_FALSE(tn::utmBand(84.5));
}

TEST(Utm, SouthernHemisphere) {
  const auto u = tn::toUtm(-33.925, 18.424);
  ASSERT_TRUE(u);
  EXPECT_FALSE(u->north);
  EXPECT_EQ(u->zone, 34);
  EXPECT_EQ(u->band, 'H');
  EXPECT_GT(u->northing, 6e6);
  EXPECT_LT(u->northing, 1e7);
  // Mirror of the northern point about the equator: same easting, northing 10 000 km minus.
  const auto n = tn::toUtm(33.925, 18.424);
  EXPECT_NEAR(u->easting, n->easting, 1e-6);
  EXPECT_NEAR(u->northing, 1e7 - n->northing, 1e-6);
}

TEST(Utm, ForcedZoneKeepsOneGridAcrossAnEdge) {
  const auto own = tn::toUtm(52.0, 6.01);  // zone 32, just east of 31's edge
  const auto forced = tn::toUtm(52.0, 6.01, 31);
  ASSERT_TRUE(own && forced);
  EXPECT_EQ(own->zone, 32);
  EXPECT_EQ(forced->zone, 31);
  EXPECT_GT(forced->easting, 700000.0);
  EXPECT_LT(own->easting, 300000.0);
  const auto back = tn::fromUtm(*forced);
  EXPECT_NEAR(back->lat_deg, 52.0, 1e-9);
  EXPECT_NEAR(back->lon_deg, 6.01, 1e-9);
  EXPECT_FALSE(tn::toUtm(52.0, 6.01, 61));
  tn::UtmPoint bad;
  bad.zone = 0;
  EXPECT_FALSE(tn::fromUtm(bad));
}

TEST(Utm, ConvergenceSignAndSize) {
  EXPECT_NEAR(tn::utmConvergence(50.0, 9.0, 32), 0.0, 1e-12);
  // East of the central meridian in the north: grid north is east of true north.
  EXPECT_GT(tn::utmConvergence(50.0, 11.0, 32), 0.0);
  EXPECT_NEAR(tn::utmConvergence(50.0, 11.0, 32), 2.0 * kDeg * std::sin(50.0 * kDeg), 1e-4);
  EXPECT_LT(tn::utmConvergence(-50.0, 11.0, 32), 0.0);
}
