#pragma once

// From what gpsd reports (a TPV fix and the receiver's GST error statistics) to what sensor_msgs/NavSatFix holds:
// the fix status, the position and an east-north-up covariance. ROS-free: the numbers of NavSatStatus and
// NavSatFix's covariance types are repeated here as enums; the node copies them into the message.

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace thorvald_gnss {

constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

/// One fix as gpsd reports it (libgps's gps_fix_t, the fields used here). Absent values are NaN.
struct GpsdFix {
  int mode = 0;              ///< gpsd's mode: 0 not seen, 1 no fix, 2 2D, 3 3D
  int status = 0;            ///< gpsd's status: 0 unknown, 1 fix, 2 DGPS, 3 RTK fixed, 4 RTK float, 5+ others
  double time_s = kUnknown;  ///< UTC of the fix (Unix seconds)
  double latitude_deg = kUnknown;
  double longitude_deg = kUnknown;
  double altitude_m = kUnknown;  ///< height above the WGS84 ellipsoid (gpsd's altHAE) [m]
  double epx_m = kUnknown;       ///< gpsd's longitude error estimate [m]
  double epy_m = kUnknown;       ///< gpsd's latitude error estimate [m]
  double epv_m = kUnknown;       ///< gpsd's vertical error estimate [m]
};

/// The receiver's error statistics (NMEA GST, gpsd's GST report): 1-sigma errors [m].
struct GpsdGst {
  double time_s = kUnknown;  ///< UTC of the statistics (Unix seconds)
  double latitude_sigma_m = kUnknown;
  double longitude_sigma_m = kUnknown;
  double altitude_sigma_m = kUnknown;
};

/// sensor_msgs/NavSatStatus status values.
enum class FixStatus { kNoFix = -1, kFix = 0, kSbasFix = 1, kGbasFix = 2 };
/// sensor_msgs/NavSatFix position_covariance_type values.
enum class CovarianceType { kUnknown = 0, kApproximated = 1, kDiagonalKnown = 2, kKnown = 3 };
/// Where the covariance came from.
enum class CovarianceSource { kNone, kGst, kGpsdErrors, kModeSigma };

/// "GST", "gpsd epx/epy/epv", "fix mode sigma", "none".
const char* covarianceSourceName(CovarianceSource source);

/// 1-sigma errors of a fix mode [m], used when neither GST nor gpsd's estimates are there.
struct ModeSigma {
  double horizontal_m = 0.0;  ///< east and north, each
  double vertical_m = 0.0;
};

/// The documented accuracy of each fix mode (defaults: the Emlid Reach RS; see README).
struct ModeSigmas {
  ModeSigma rtk_fixed{0.010, 0.020};
  ModeSigma rtk_float{0.30, 0.50};
  ModeSigma dgps{0.50, 1.00};
  ModeSigma single{1.5, 2.5};
  /// How old a GST may be against the fix it describes [s]; older ones are not used.
  double gst_max_age_s = 1.5;

  /// Problems, empty when usable ("rtk_fixed.horizontal_m: -1 is not > 0").
  std::vector<std::string> validate() const;
};

/// What the node publishes for one gpsd fix.
struct NavFix {
  FixStatus status = FixStatus::kNoFix;
  int gpsd_status = 0;  ///< gpsd's status, for diagnostics
  double time_s = kUnknown;
  double latitude_deg = kUnknown;
  double longitude_deg = kUnknown;
  double altitude_m = kUnknown;  ///< NaN for a 2D fix
  /// East-north-up covariance [m^2], row-major as NavSatFix holds it.
  std::array<double, 9> covariance{};
  CovarianceType covariance_type = CovarianceType::kUnknown;
  CovarianceSource covariance_source = CovarianceSource::kNone;
  /// gpsd reported this epoch before (it reports one after each sentence of an epoch): publish the first only.
  bool repeat = false;
};

/// Turns gpsd's fixes into NavSatFix content. Status: RTK fixed and float -> GBAS, DGPS -> SBAS, any other 2D or 3D
/// fix -> FIX, mode 0 or 1 -> NO_FIX. Covariance (diagonal, east-north-up), first that applies:
/// 1. the latest GST, if it is at most gst_max_age_s older than the fix and not older than the last change of
///    gpsd's status (a GST of an RTK fix says nothing about the single fix after it): DIAGONAL_KNOWN;
/// 2. gpsd's epx, epy, epv when all three are given: DIAGONAL_KNOWN;
/// 3. the fix mode's sigma from ModeSigmas: APPROXIMATED.
/// A 2D fix has no altitude: its vertical variance is that of the mode sigma times 100.
class FixConverter {
 public:
  /// Throws std::invalid_argument naming the problems of `sigmas`.
  explicit FixConverter(ModeSigmas sigmas);

  /// Keeps the receiver's latest error statistics; rejects (returns false) statistics that are not finite and > 0.
  bool addGst(const GpsdGst& gst);
  /// The NavSatFix content of `fix`.
  NavFix convert(const GpsdFix& fix);

 private:
  const ModeSigma& modeSigma(int gpsd_status) const;

  ModeSigmas sigmas_;
  std::optional<GpsdGst> gst_;
  int last_status_ = -1;
  bool any_report_ = false;  ///< a fix report was converted before
  double last_time_s_ = kUnknown;
  int last_mode_ = -1;
  double status_since_s_ = kUnknown;
};

}  // namespace thorvald_gnss
