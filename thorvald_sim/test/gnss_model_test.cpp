// The GNSS receiver model and its NMEA writer: sentences against hand-computed ones (checksums worked out by XOR
// of the characters by hand), the error statistics of each fix state, outages, obstacle zones, and a round trip
// through the small NMEA parser below.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "thorvald_sim/gnss_model.h"
#include "thorvald_sim/nmea_sentences.h"

namespace thorvald_sim {
namespace {

// ---- A small NMEA reader, independent of the writer, for the round trip. ----

/// The fields of a sentence after its address ("GNGGA"), or nothing when the framing or checksum is wrong.
std::optional<std::vector<std::string>> parseSentence(const std::string& sentence, std::string* address) {
  if (sentence.size() < 6 || sentence[0] != '$' || sentence.substr(sentence.size() - 2) != "\r\n") return {};
  const size_t star = sentence.find('*');
  if (star == std::string::npos || star + 5 != sentence.size()) return {};
  int sum = 0;
  for (size_t i = 1; i < star; ++i) sum ^= static_cast<unsigned char>(sentence[i]);
  if (sum != std::strtol(sentence.substr(star + 1, 2).c_str(), nullptr, 16)) return {};
  std::vector<std::string> fields;
  std::stringstream body(sentence.substr(1, star - 1));
  std::string field;
  while (std::getline(body, field, ',')) fields.push_back(field);
  if (sentence[star - 1] == ',') fields.push_back("");  // getline drops a trailing empty field
  *address = fields.front();
  fields.erase(fields.begin());
  return fields;
}

/// "ddmm.mmmm" + hemisphere to signed degrees.
double parseDegrees(const std::string& value, const std::string& hemisphere, int degree_digits) {
  const double degrees = std::stod(value.substr(0, degree_digits));
  const double minutes = std::stod(value.substr(degree_digits));
  const double sign = (hemisphere == "S" || hemisphere == "W") ? -1.0 : 1.0;
  return sign * (degrees + minutes / 60.0);
}

GnssSolution fixedSolution() {
  GnssSolution s;
  s.utc_s = 1625097600.0 + 3723.456;  // 2021-07-01 01:02:03.456
  s.state = GnssFixState::kFixed;
  s.latitude_deg = 48.1173;              // 48 deg 07.038 min
  s.longitude_deg = 11.0 + 31.0 / 60.0;  // 11 deg 31 min
  s.altitude_m = 545.4;
  s.sigma_m = {0.010, 0.010, 0.020};
  s.satellites = 18;
  s.hdop = 0.6;
  s.speed_mps = 1.0;  // 1.943844 knots
  s.course_deg = 90.0;
  return s;
}

TEST(NmeaSentences, ChecksumOfAWellKnownSentence) {
  EXPECT_EQ(nmeaChecksum("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"), "47");
  EXPECT_EQ(nmeaChecksum(""), "00");
  EXPECT_EQ(nmeaSentence("A"), "$A*41\r\n");  // 'A' = 0x41
}

TEST(NmeaSentences, LatitudeLongitudeAndTimeFields) {
  EXPECT_EQ(nmeaLatitude(48.1173), "4807.0380000,N");
  EXPECT_EQ(nmeaLatitude(-33.5), "3330.0000000,S");
  EXPECT_EQ(nmeaLatitude(5.0 + 1.0 / 60.0), "0501.0000000,N");
  EXPECT_EQ(nmeaLatitude(33.999999999999), "3400.0000000,N");  // minutes round up into the next degree
  EXPECT_EQ(nmeaLongitude(-83.5), "08330.0000000,W");
  EXPECT_EQ(nmeaLongitude(11.0 + 31.0 / 60.0), "01131.0000000,E");
  EXPECT_EQ(nmeaLongitude(-0.0001), "00000.0060000,W");
  EXPECT_EQ(nmeaTime(1625097600.0), "000000.00");
  EXPECT_EQ(nmeaTime(1625097600.0 + 3723.456), "010203.46");
  EXPECT_EQ(nmeaTime(1625097600.0 - 0.001), "000000.00");  // rounds into the next day
  EXPECT_EQ(nmeaDate(1625097600.0 - 0.001), "010721");
  EXPECT_EQ(nmeaDate(1625097600.0 - 1.0), "300621");
}

TEST(NmeaSentences, FixedEpochAgainstHandWrittenSentences) {
  const GnssSolution s = fixedSolution();
  EXPECT_EQ(ggaSentence(s),
            "$GNGGA,010203.46,4807.0380000,N,01131.0000000,E,4,18,0.6,545.400,M,0.000,M,1.0,0000*67\r\n");
  EXPECT_EQ(rmcSentence(s), "$GNRMC,010203.46,A,4807.0380000,N,01131.0000000,E,1.944,90.00,010721,,,R*57\r\n");
  EXPECT_EQ(gstSentence(s), "$GNGST,010203.46,0.014,0.010,0.010,0.0,0.010,0.010,0.020*4C\r\n");
  EXPECT_EQ(epochSentences(s).size(), 3u);
}

TEST(NmeaSentences, NoFixEpochHasEmptyPositionAndNoGst) {
  GnssSolution s;
  s.utc_s = 1625097600.0;
  EXPECT_EQ(ggaSentence(s), "$GNGGA,000000.00,,,,,0,00,99.99,,,,,,*78\r\n");
  EXPECT_EQ(gstSentence(s), "");
  const auto sentences = epochSentences(s);
  ASSERT_EQ(sentences.size(), 2u);
  std::string address;
  const auto rmc = parseSentence(sentences[1], &address);
  ASSERT_TRUE(rmc);
  EXPECT_EQ(address, "GNRMC");
  EXPECT_EQ((*rmc)[1], "V");
  EXPECT_EQ(rmc->back(), "N");
}

TEST(NmeaSentences, QualityPerState) {
  EXPECT_EQ(ggaQuality(GnssFixState::kNoFix), 0);
  EXPECT_EQ(ggaQuality(GnssFixState::kSingle), 1);
  EXPECT_EQ(ggaQuality(GnssFixState::kFloat), 5);
  EXPECT_EQ(ggaQuality(GnssFixState::kFixed), 4);
}

TEST(GeodeticDatum, RoundTripAndScale) {
  const GeodeticDatum datum{33.0, -83.0, 100.0};
  const Eigen::Vector3d enu(123.4, -567.8, 2.5);
  const Eigen::Vector3d geo = datum.toGeodetic(enu);
  EXPECT_LT((datum.toEnu(geo.x(), geo.y(), geo.z()) - enu).norm(), 1e-9);
  // 1 km north is about 1 / 110.9 km per degree of latitude at 33 deg (WGS84 meridian arc: 110.905 km).
  EXPECT_NEAR(datum.toGeodetic({0.0, 1000.0, 0.0}).x() - 33.0, 1.0 / 110.905, 1e-5);
}

// ---- The receiver model. ----

/// Model time [s] at which a receiver that sees the whole sky since 0 reaches `state` (defaults).
double acquiredAt(const GnssModelParams& p, GnssFixState state) {
  double t = p.single_acquire_s;
  if (state >= GnssFixState::kFloat) t += p.float_acquire_s;
  if (state >= GnssFixState::kFixed) t += p.fixed_acquire_s;
  return t;
}

/// Runs a standing receiver held in `state` by a zone over everything (fixed: no zone) for 2000 correlation times
/// and checks each axis's error sigma within 10 % of the profile and the lag-one correlation of the Gauss-Markov
/// process (exp(-dt / tau), within 0.02).
void checkStatistics(GnssFixState state, const GnssStateProfile& profile) {
  GnssModelParams p;
  p.seed = 7;
  if (state != GnssFixState::kFixed) p.zones.push_back({0.0, 0.0, 1e6, state});
  GnssModel model(p);
  const Eigen::Vector3d truth(10.0, 20.0, 1.0);
  const double start_s = acquiredAt(p, state);
  const long epochs = static_cast<long>(2000.0 * profile.correlation_time_s * p.rate_hz);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero(), lag = Eigen::Vector3d::Zero();
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  long n = 0;
  for (long k = 0; n < epochs; ++k) {
    const auto sol = model.update(static_cast<double>(k) / p.rate_hz, truth);
    ASSERT_TRUE(sol) << "an epoch every 1 / rate";
    if (sol->time_s < start_s) continue;
    ASSERT_EQ(sol->state, state) << "at " << sol->time_s << " s";
    const Eigen::Vector3d e = sol->enu_m - truth;
    sum += e;
    sum_sq += e.cwiseProduct(e);
    if (n > 0) lag += e.cwiseProduct(previous);
    previous = e;
    ++n;
  }
  const Eigen::Vector3d sigma(profile.sigma_horizontal_m, profile.sigma_horizontal_m, profile.sigma_vertical_m);
  const double rho = std::exp(-1.0 / (p.rate_hz * profile.correlation_time_s));
  for (int i = 0; i < 3; ++i) {
    const double mean = sum[i] / n;
    const double var = sum_sq[i] / n - mean * mean;
    EXPECT_NEAR(std::sqrt(var), sigma[i], 0.10 * sigma[i]) << gnssFixStateName(state) << " axis " << i;
    EXPECT_NEAR(mean, 0.0, 0.15 * sigma[i]) << gnssFixStateName(state) << " axis " << i;
    EXPECT_NEAR(lag[i] / (n - 1) / var, rho, 0.02) << gnssFixStateName(state) << " axis " << i;
  }
}

TEST(GnssModel, ErrorStatisticsOfEachState) {
  const GnssModelParams p;
  checkStatistics(GnssFixState::kFixed, p.fixed);
  checkStatistics(GnssFixState::kFloat, p.floating);
  checkStatistics(GnssFixState::kSingle, p.single);
}

TEST(GnssModel, AcquiresStateByStateAtFiveHertz) {
  const GnssModelParams p;
  GnssModel model(p);
  int epochs = 0;
  std::map<GnssFixState, double> first_seen;
  for (int k = 0; k <= 2000; ++k) {  // fed at 100 Hz for 20 s
    const auto sol = model.update(k * 0.01, Eigen::Vector3d::Zero());
    if (!sol) continue;
    ++epochs;
    if (!first_seen.count(sol->state)) first_seen[sol->state] = sol->time_s;
  }
  EXPECT_EQ(epochs, 101);
  EXPECT_DOUBLE_EQ(first_seen.at(GnssFixState::kNoFix), 0.0);
  EXPECT_NEAR(first_seen.at(GnssFixState::kSingle), acquiredAt(p, GnssFixState::kSingle), 1e-9);
  EXPECT_NEAR(first_seen.at(GnssFixState::kFloat), acquiredAt(p, GnssFixState::kFloat), 1e-9);
  EXPECT_NEAR(first_seen.at(GnssFixState::kFixed), acquiredAt(p, GnssFixState::kFixed), 1e-9);
}

TEST(GnssModel, OutageGivesNoFixSentencesThenReacquires) {
  GnssModelParams p;
  p.outages.push_back({30.0, 40.0});
  GnssModel model(p);
  std::string address;
  for (int k = 0; k <= 5 * 60; ++k) {
    const double t = k / p.rate_hz;
    const auto sol = model.update(t, Eigen::Vector3d(0.5 * t, 0.0, 0.0));
    ASSERT_TRUE(sol);
    const auto sentences = epochSentences(*sol);
    const auto gga = parseSentence(sentences.front(), &address);
    ASSERT_TRUE(gga) << sentences.front();
    const int quality = std::stoi((*gga)[5]);
    if (t >= 30.0 && t < 40.0) {
      EXPECT_EQ(quality, 0) << t;
      EXPECT_EQ((*gga)[1], "") << "no latitude in an outage";
      EXPECT_EQ(sentences.size(), 2u) << "no GST in an outage";
    } else if (t >= 20.0 && t < 30.0) {
      EXPECT_EQ(quality, 4) << t;
    } else if (t >= 40.0 + acquiredAt(p, GnssFixState::kFixed)) {
      EXPECT_EQ(quality, 4) << t;
    } else if (t >= 40.0 && t < 40.0 + p.single_acquire_s) {
      EXPECT_EQ(quality, 0) << t;
    }
  }
}

TEST(GnssModel, ObstacleZoneCapsTheState) {
  GnssModelParams p;
  p.zones.push_back({100.0, 0.0, 10.0, GnssFixState::kSingle});  // a shed 100 m east
  p.zones.push_back({200.0, 0.0, 5.0, GnssFixState::kFloat});    // tall crop 200 m east
  GnssModel model(p);
  EXPECT_EQ(model.availableState(0.0, {95.0, 0.0, 0.0}), GnssFixState::kSingle);
  EXPECT_EQ(model.availableState(0.0, {100.0, 11.0, 0.0}), GnssFixState::kFixed);
  EXPECT_EQ(model.availableState(0.0, {203.0, 0.0, 0.0}), GnssFixState::kFloat);
  // Driving east at 2 m/s: fixed before the shed, single within it, fixed again 13 s after leaving it.
  std::map<double, GnssFixState> states;
  for (int k = 0; k <= 5 * 100; ++k) {
    const double t = k / p.rate_hz;
    const auto sol = model.update(t, Eigen::Vector3d(2.0 * t, 0.0, 0.0));
    states[t] = sol->state;
  }
  EXPECT_EQ(states.at(40.0), GnssFixState::kFixed);   // x = 80 m
  EXPECT_EQ(states.at(46.0), GnssFixState::kSingle);  // x = 92 m
  EXPECT_EQ(states.at(54.0), GnssFixState::kSingle);  // x = 108 m
  EXPECT_EQ(states.at(56.0), GnssFixState::kSingle);  // x = 112 m: left at 55 s, float needs 3 s
  EXPECT_EQ(states.at(59.0), GnssFixState::kFloat);
  EXPECT_EQ(states.at(69.0), GnssFixState::kFixed);
}

TEST(GnssModel, RoundTripThroughAnNmeaParser) {
  GnssModelParams p;
  p.datum_latitude_deg = 31.4747;
  p.datum_longitude_deg = -83.5283;
  GnssModel model(p);
  const GeodeticDatum datum{p.datum_latitude_deg, p.datum_longitude_deg, p.datum_altitude_m};
  std::string address;
  int checked = 0;
  for (int k = 0; k <= 5 * 30; ++k) {
    const double t = k / p.rate_hz;
    const auto sol = model.update(t, Eigen::Vector3d(30.0 + 1.5 * t, -12.0 + 0.5 * t, 1.2));
    if (sol->state == GnssFixState::kNoFix) continue;
    const auto sentences = epochSentences(*sol);
    const auto gga = parseSentence(sentences[0], &address);
    ASSERT_TRUE(gga);
    EXPECT_EQ(address, "GNGGA");
    const double lat = parseDegrees((*gga)[1], (*gga)[2], 2);
    const double lon = parseDegrees((*gga)[3], (*gga)[4], 3);
    EXPECT_NEAR(lat, sol->latitude_deg, 2e-9);  // 1e-7 minute is 1.7e-9 deg
    EXPECT_NEAR(lon, sol->longitude_deg, 2e-9);
    EXPECT_NEAR(std::stod((*gga)[8]), sol->altitude_m, 5e-4);
    EXPECT_EQ(std::stoi((*gga)[6]), sol->satellites);
    // Back in the local frame the parsed position is the model's, to well under a millimetre.
    EXPECT_LT((datum.toEnu(lat, lon, std::stod((*gga)[8])) - sol->enu_m).norm(), 1e-3);
    const auto rmc = parseSentence(sentences[1], &address);
    ASSERT_TRUE(rmc);
    EXPECT_EQ((*rmc)[8], "010721");
    if (t > 0.0) {
      EXPECT_NEAR(std::stod((*rmc)[6]) * 1852.0 / 3600.0, std::hypot(1.5, 0.5), 1e-3);
    }
    const auto gst = parseSentence(sentences[2], &address);
    ASSERT_TRUE(gst);
    EXPECT_NEAR(std::stod((*gst)[5]), sol->sigma_m.y(), 5e-4);
    EXPECT_NEAR(std::stod((*gst)[7]), sol->sigma_m.z(), 5e-4);
    ++checked;
  }
  EXPECT_GT(checked, 140);
}

TEST(GnssModel, RejectsBadParameters) {
  GnssModelParams p;
  p.rate_hz = 0.0;
  p.fixed.sigma_horizontal_m = -1.0;
  p.outages.push_back({5.0, 5.0});
  EXPECT_EQ(p.validate().size(), 3u);
  EXPECT_THROW(GnssModel{p}, std::invalid_argument);
  GnssModel ok{GnssModelParams{}};
  ok.update(1.0, Eigen::Vector3d::Zero());
  EXPECT_THROW(ok.update(0.5, Eigen::Vector3d::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace thorvald_sim
