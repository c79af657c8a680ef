#pragma once

// NMEA 0183 output of the GNSS receiver model (gnss_model.h): GGA (position, fix quality, satellites, HDOP,
// height), RMC (position, speed, course, date) and GST (the receiver's error statistics, which gpsd reports as
// GST and the client turns into a covariance), as an RTK receiver writes them: talker GN, latitude and longitude
// to 1e-7 minute, UTC to the centisecond, "*hh" checksums and CR LF endings. ROS-free.

#include <string>
#include <vector>

#include "thorvald_sim/gnss_model.h"

namespace thorvald_sim {

/// How the sentences are written.
struct NmeaOptions {
  std::string talker = "GN";      ///< two letters: GN (any constellation) or GP (GPS only)
  double correction_age_s = 1.0;  ///< GGA's age of the RTK corrections when float or fixed [s]
  int base_station_id = 0;        ///< GGA's reference station id (0..1023)
};

/// The two hex digits (upper case) of the XOR of every character of `body` (the text between '$' and '*').
std::string nmeaChecksum(const std::string& body);
/// "$" + body + "*" + checksum + "\r\n".
std::string nmeaSentence(const std::string& body);

/// "ddmm.mmmmmmm,N" or ",S" (minutes rounded to 1e-7).
std::string nmeaLatitude(double latitude_deg);
/// "dddmm.mmmmmmm,E" or ",W".
std::string nmeaLongitude(double longitude_deg);
/// "hhmmss.ss" of a UTC time (Unix seconds, rounded to the centisecond).
std::string nmeaTime(double utc_s);
/// "ddmmyy" of a UTC time (Unix seconds, rounded to the centisecond as nmeaTime).
std::string nmeaDate(double utc_s);

/// GGA quality of a fix state: 0 none, 1 single, 5 float, 4 fixed.
int ggaQuality(GnssFixState state);

/// GGA: the position with quality, satellites, HDOP and height (ellipsoidal height in the altitude field, geoid
/// separation 0); empty position fields and quality 0 without a fix.
std::string ggaSentence(const GnssSolution& solution, const NmeaOptions& options = {});
/// RMC: status A with the position, speed [knots], course and date; status V and mode N without a fix.
std::string rmcSentence(const GnssSolution& solution, const NmeaOptions& options = {});
/// GST: the receiver's 1-sigma errors (circular ellipse, latitude, longitude, height) [m]; empty without a fix.
std::string gstSentence(const GnssSolution& solution, const NmeaOptions& options = {});
/// The sentences of one epoch in the order the receiver sends them: GGA, RMC, then GST when there is a fix.
std::vector<std::string> epochSentences(const GnssSolution& solution, const NmeaOptions& options = {});

}  // namespace thorvald_sim
