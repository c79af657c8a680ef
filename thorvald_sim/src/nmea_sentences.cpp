#include "thorvald_sim/nmea_sentences.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>

namespace thorvald_sim {
namespace {

constexpr double kKnotsPerMps = 3600.0 / 1852.0;

/// `value` [deg] as degrees and minutes with 7 decimals, the degrees on `degree_digits` digits, then the hemisphere.
std::string degreesMinutes(double value, int degree_digits, char positive, char negative) {
  const long long units_per_minute = 10000000LL;  // 1e-7 minute
  const long long total = std::llround(std::abs(value) * 60.0 * static_cast<double>(units_per_minute));
  const long long degrees = total / (60 * units_per_minute);
  const long long rest = total % (60 * units_per_minute);
  char text[40];
  std::snprintf(text, sizeof(text), "%0*lld%02lld.%07lld,%c", degree_digits, degrees, rest / units_per_minute,
                rest % units_per_minute, value < 0.0 ? negative : positive);
  return text;
}

/// The broken-down UTC of `utc_s` rounded to the centisecond, and the centiseconds.
std::tm brokenDown(double utc_s, int& centiseconds) {
  const long long cs = std::llround(utc_s * 100.0);
  const std::time_t seconds = static_cast<std::time_t>(cs / 100);
  centiseconds = static_cast<int>(cs % 100);
  std::tm t{};
  gmtime_r(&seconds, &t);
  return t;
}

std::string fixed(double value, int decimals) {
  char text[48];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

bool hasFix(const GnssSolution& s) { return s.state != GnssFixState::kNoFix; }

}  // namespace

std::string nmeaChecksum(const std::string& body) {
  unsigned char sum = 0;
  for (const char c : body) sum ^= static_cast<unsigned char>(c);
  char text[3];
  std::snprintf(text, sizeof(text), "%02X", sum);
  return text;
}

std::string nmeaSentence(const std::string& body) { return "$" + body + "*" + nmeaChecksum(body) + "\r\n"; }

std::string nmeaLatitude(double latitude_deg) { return degreesMinutes(latitude_deg, 2, 'N', 'S'); }

std::string nmeaLongitude(double longitude_deg) { return degreesMinutes(longitude_deg, 3, 'E', 'W'); }

std::string nmeaTime(double utc_s) {
  int cs = 0;
  const std::tm t = brokenDown(utc_s, cs);
  char text[48];
  std::snprintf(text, sizeof(text), "%02d%02d%02d.%02d", t.tm_hour, t.tm_min, t.tm_sec, cs);
  return text;
}

std::string nmeaDate(double utc_s) {
  int cs = 0;
  const std::tm t = brokenDown(utc_s, cs);
  char text[48];
  std::snprintf(text, sizeof(text), "%02d%02d%02d", t.tm_mday, t.tm_mon + 1, t.tm_year % 100);
  return text;
}

int ggaQuality(GnssFixState state) {
  switch (state) {
    case GnssFixState::kSingle:
      return 1;
    case GnssFixState::kFloat:
      return 5;
    case GnssFixState::kFixed:
      return 4;
    default:
      return 0;
  }
}

std::string ggaSentence(const GnssSolution& s, const NmeaOptions& o) {
  std::string body = o.talker + "GGA," + nmeaTime(s.utc_s) + ",";
  if (!hasFix(s)) return nmeaSentence(body + ",,,,0,00,99.99,,,,,,");
  char satellites[8];
  std::snprintf(satellites, sizeof(satellites), "%02d", s.satellites);
  const bool rtk = s.state == GnssFixState::kFloat || s.state == GnssFixState::kFixed;
  char station[8];
  std::snprintf(station, sizeof(station), "%04d", o.base_station_id);
  body += nmeaLatitude(s.latitude_deg) + "," + nmeaLongitude(s.longitude_deg) + "," +
          std::to_string(ggaQuality(s.state)) + "," + satellites + "," + fixed(s.hdop, 1) + "," +
          fixed(s.altitude_m, 3) + ",M,0.000,M," + (rtk ? fixed(o.correction_age_s, 1) + "," + station : ",");
  return nmeaSentence(body);
}

std::string rmcSentence(const GnssSolution& s, const NmeaOptions& o) {
  std::string body = o.talker + "RMC," + nmeaTime(s.utc_s) + ",";
  if (!hasFix(s)) return nmeaSentence(body + "V,,,,,,," + nmeaDate(s.utc_s) + ",,,N");
  const char mode = s.state == GnssFixState::kFixed ? 'R' : s.state == GnssFixState::kFloat ? 'F' : 'A';
  body += "A," + nmeaLatitude(s.latitude_deg) + "," + nmeaLongitude(s.longitude_deg) + "," +
          fixed(s.speed_mps * kKnotsPerMps, 3) + "," + fixed(s.course_deg, 2) + "," + nmeaDate(s.utc_s) + ",,," + mode;
  return nmeaSentence(body);
}

std::string gstSentence(const GnssSolution& s, const NmeaOptions& o) {
  if (!hasFix(s)) return "";
  const double horizontal = std::hypot(s.sigma_m.x(), s.sigma_m.y());
  // Semi-major and semi-minor axes of the 1-sigma ellipse: the larger and smaller axis sigma (east-north aligned).
  const double major = std::max(s.sigma_m.x(), s.sigma_m.y());
  const double minor = std::min(s.sigma_m.x(), s.sigma_m.y());
  const double orientation = s.sigma_m.y() >= s.sigma_m.x() ? 0.0 : 90.0;
  const std::string body = o.talker + "GST," + nmeaTime(s.utc_s) + "," + fixed(horizontal, 3) + "," + fixed(major, 3) +
                           "," + fixed(minor, 3) + "," + fixed(orientation, 1) + "," + fixed(s.sigma_m.y(), 3) + "," +
                           fixed(s.sigma_m.x(), 3) + "," + fixed(s.sigma_m.z(), 3);
  return nmeaSentence(body);
}

std::vector<std::string> epochSentences(const GnssSolution& s, const NmeaOptions& o) {
  std::vector<std::string> out{ggaSentence(s, o), rmcSentence(s, o)};
  if (hasFix(s)) out.push_back(gstSentence(s, o));
  return out;
}

}  // namespace thorvald_sim
