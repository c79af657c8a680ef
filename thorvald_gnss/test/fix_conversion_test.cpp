// gpsd fixes to NavSatFix content: status per gpsd status and mode, the covariance rule (GST, then gpsd's
// estimates, then the mode's sigma), stale GSTs, repeated epochs, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "thorvald_gnss/fix_conversion.h"

namespace thorvald_gnss {
namespace {

GpsdFix fixAt(double time_s, int status, int mode = 3) {
  GpsdFix f;
  f.mode = mode;
  f.status = status;
  f.time_s = time_s;
  f.latitude_deg = 33.0000001;
  f.longitude_deg = -83.0000002;
  f.altitude_m = 101.5;
  return f;
}

GpsdGst gstAt(double time_s, double lat_m, double lon_m, double alt_m) { return {time_s, lat_m, lon_m, alt_m}; }

void expectDiagonal(const NavFix& f, double east_m, double north_m, double up_m) {
  EXPECT_DOUBLE_EQ(f.covariance[0], east_m * east_m);
  EXPECT_DOUBLE_EQ(f.covariance[4], north_m * north_m);
  EXPECT_DOUBLE_EQ(f.covariance[8], up_m * up_m);
  for (int i : {1, 2, 3, 5, 6, 7}) EXPECT_EQ(f.covariance[i], 0.0);
}

TEST(FixConverter, StatusFromGpsdStatusAndMode) {
  FixConverter c{ModeSigmas{}};
  EXPECT_EQ(c.convert(fixAt(1.0, 3)).status, FixStatus::kGbasFix);  // RTK fixed
  EXPECT_EQ(c.convert(fixAt(2.0, 4)).status, FixStatus::kGbasFix);  // RTK float
  EXPECT_EQ(c.convert(fixAt(3.0, 2)).status, FixStatus::kSbasFix);  // DGPS
  EXPECT_EQ(c.convert(fixAt(4.0, 1)).status, FixStatus::kFix);
  EXPECT_EQ(c.convert(fixAt(5.0, 0)).status, FixStatus::kFix);  // gpsd leaves a plain fix's status out of its JSON
  const NavFix none = c.convert(fixAt(6.0, 3, 1));              // mode 1: no fix whatever the status says
  EXPECT_EQ(none.status, FixStatus::kNoFix);
  EXPECT_EQ(none.covariance_type, CovarianceType::kUnknown);
  EXPECT_TRUE(std::isnan(none.latitude_deg));
  EXPECT_EQ(c.convert(fixAt(7.0, 3, 0)).status, FixStatus::kNoFix);  // mode not seen
  GpsdFix no_position = fixAt(8.0, 1);
  no_position.latitude_deg = kUnknown;
  EXPECT_EQ(c.convert(no_position).status, FixStatus::kNoFix);
}

TEST(FixConverter, PositionAndTwoDFix) {
  FixConverter c{ModeSigmas{}};
  const NavFix f = c.convert(fixAt(1.0, 3));
  EXPECT_DOUBLE_EQ(f.latitude_deg, 33.0000001);
  EXPECT_DOUBLE_EQ(f.longitude_deg, -83.0000002);
  EXPECT_DOUBLE_EQ(f.altitude_m, 101.5);
  const NavFix flat = c.convert(fixAt(2.0, 1, 2));
  EXPECT_TRUE(std::isnan(flat.altitude_m));
  expectDiagonal(flat, 1.5, 1.5, 25.0);  // single's 2.5 m vertical sigma times 10 for the unknown height
}

TEST(FixConverter, CovarianceFromModeSigmaWithoutGstOrEstimates) {
  FixConverter c{ModeSigmas{}};
  const NavFix fixed = c.convert(fixAt(1.0, 3));
  EXPECT_EQ(fixed.covariance_type, CovarianceType::kApproximated);
  EXPECT_EQ(fixed.covariance_source, CovarianceSource::kModeSigma);
  expectDiagonal(fixed, 0.010, 0.010, 0.020);
  expectDiagonal(c.convert(fixAt(2.0, 4)), 0.30, 0.30, 0.50);
  expectDiagonal(c.convert(fixAt(3.0, 2)), 0.50, 0.50, 1.00);
  expectDiagonal(c.convert(fixAt(4.0, 1)), 1.5, 1.5, 2.5);
}

TEST(FixConverter, CovarianceFromGpsdEstimates) {
  FixConverter c{ModeSigmas{}};
  GpsdFix f = fixAt(1.0, 1);
  f.epx_m = 2.0;
  f.epy_m = 3.0;
  f.epv_m = 4.0;
  const NavFix out = c.convert(f);
  EXPECT_EQ(out.covariance_type, CovarianceType::kDiagonalKnown);
  EXPECT_EQ(out.covariance_source, CovarianceSource::kGpsdErrors);
  expectDiagonal(out, 2.0, 3.0, 4.0);  // east from epx (longitude), north from epy (latitude)
  f.time_s = 2.0;
  f.epv_m = kUnknown;  // incomplete: the mode's sigma
  EXPECT_EQ(c.convert(f).covariance_source, CovarianceSource::kModeSigma);
}

TEST(FixConverter, CovarianceFromGstWhileCurrent) {
  FixConverter c{ModeSigmas{}};
  c.convert(fixAt(9.8, 3));
  ASSERT_TRUE(c.addGst(gstAt(9.8, 0.012, 0.011, 0.025)));
  const NavFix f = c.convert(fixAt(10.0, 3));
  EXPECT_EQ(f.covariance_type, CovarianceType::kDiagonalKnown);
  EXPECT_EQ(f.covariance_source, CovarianceSource::kGst);
  expectDiagonal(f, 0.011, 0.012, 0.025);  // east from the longitude sigma, north from the latitude sigma
  EXPECT_EQ(c.convert(fixAt(11.2, 3)).covariance_source, CovarianceSource::kGst);        // 1.4 s old: still used
  EXPECT_EQ(c.convert(fixAt(11.4, 3)).covariance_source, CovarianceSource::kModeSigma);  // too old
}

TEST(FixConverter, GstOfAnEarlierFixStatusIsNotUsed) {
  FixConverter c{ModeSigmas{}};
  c.convert(fixAt(10.0, 3));
  c.addGst(gstAt(10.0, 0.01, 0.01, 0.02));
  const NavFix single = c.convert(fixAt(10.2, 1));  // RTK lost: the fixed solution's GST says nothing of this one
  EXPECT_EQ(single.covariance_source, CovarianceSource::kModeSigma);
  expectDiagonal(single, 1.5, 1.5, 2.5);
  c.addGst(gstAt(10.2, 1.4, 1.6, 2.4));
  EXPECT_EQ(c.convert(fixAt(10.4, 1)).covariance_source, CovarianceSource::kGst);
}

TEST(FixConverter, RepeatedEpochIsMarked) {
  FixConverter c{ModeSigmas{}};
  EXPECT_FALSE(c.convert(fixAt(1.0, 3)).repeat);
  EXPECT_TRUE(c.convert(fixAt(1.0, 3)).repeat);  // gpsd's second report of the same epoch
  EXPECT_FALSE(c.convert(fixAt(1.2, 3)).repeat);
  EXPECT_FALSE(c.convert(fixAt(1.2, 1, 1)).repeat);  // same time, the mode changed
  GpsdFix untimed = fixAt(kUnknown, 0, 1);
  EXPECT_FALSE(c.convert(untimed).repeat);
  EXPECT_TRUE(c.convert(untimed).repeat);
}

TEST(FixConverter, RejectsBadGstAndBadSigmas) {
  FixConverter c{ModeSigmas{}};
  EXPECT_FALSE(c.addGst(gstAt(1.0, kUnknown, 0.1, 0.1)));
  EXPECT_FALSE(c.addGst(gstAt(1.0, 0.1, 0.0, 0.1)));
  EXPECT_FALSE(c.addGst(gstAt(kUnknown, 0.1, 0.1, 0.1)));
  EXPECT_EQ(c.convert(fixAt(1.0, 3)).covariance_source, CovarianceSource::kModeSigma);
  ModeSigmas bad;
  bad.rtk_fixed.horizontal_m = 0.0;
  bad.single.vertical_m = -1.0;
  bad.gst_max_age_s = kUnknown;
  EXPECT_EQ(bad.validate().size(), 3u);
  EXPECT_THROW(FixConverter{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace thorvald_gnss
