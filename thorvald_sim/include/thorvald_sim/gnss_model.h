#pragma once

// A model of an RTK-GNSS receiver (the cotton rover's Emlid Reach RS, 5 Hz): from the antenna's true position in a
// local east-north-up frame it makes the receiver's solution, with the fix state an RTK receiver reports (fixed,
// float, single, none), errors that are correlated in time (first-order Gauss-Markov, so a position does not jump
// every epoch), outages (scheduled intervals) and zones near tall crop or structures where multipath or a blocked
// sky caps the state (float, single or no fix). ROS-free; nmea_sentences.h turns a solution into NMEA.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace thorvald_sim {

/// The receiver's solution type, ordered from worst to best (NMEA GGA quality 0, 1, 5, 4).
enum class GnssFixState { kNoFix = 0, kSingle = 1, kFloat = 2, kFixed = 3 };

/// "no fix", "single", "float", "fixed".
const char* gnssFixStateName(GnssFixState state);

/// What a receiver delivers in one fix state.
struct GnssStateProfile {
  double sigma_horizontal_m = 0.0;  ///< 1-sigma error of east and of north (each axis) [m]
  double sigma_vertical_m = 0.0;    ///< 1-sigma error of up [m]
  double correlation_time_s = 1.0;  ///< time constant of the Gauss-Markov error [s]
  int satellites = 0;               ///< satellites used, as GGA reports them
  double hdop = 99.99;              ///< horizontal dilution of precision, as GGA reports it
};

/// A scheduled outage: no fix from `start_s` to `end_s` [s of model time].
struct GnssOutage {
  double start_s = 0.0;
  double end_s = 0.0;
};

/// A zone around an obstacle (tall crop, a shed, a tree line): inside `radius_m` of (`east_m`, `north_m`) the
/// receiver's state is at best `best_state` (kNoFix: an outage zone).
struct GnssZone {
  double east_m = 0.0;
  double north_m = 0.0;
  double radius_m = 0.0;
  GnssFixState best_state = GnssFixState::kFloat;
};

/// The receiver and its surroundings. Defaults: the Emlid Reach RS of the cotton rover (see README of thorvald_gnss
/// and the report's table for where each figure comes from).
struct GnssModelParams {
  double rate_hz = 5.0;              ///< solution rate [Hz]
  double datum_latitude_deg = 33.0;  ///< WGS84 latitude of the local frame's origin [deg]
  double datum_longitude_deg = -83.0;
  double datum_altitude_m = 100.0;    ///< WGS84 ellipsoidal height of the origin [m]
  double utc_start_s = 1625097600.0;  ///< UTC (Unix seconds) at model time 0; default 2021-07-01 00:00:00
  /// RTK fixed: 7 mm + 1 ppm horizontal, 14 mm + 1 ppm vertical over a 3 km baseline, rounded up to 1 cm / 2 cm.
  GnssStateProfile fixed{0.010, 0.020, 2.0, 18, 0.6};
  GnssStateProfile floating{0.30, 0.50, 15.0, 14, 0.9};
  GnssStateProfile single{1.5, 2.5, 60.0, 10, 1.3};
  double single_acquire_s = 1.0;  ///< no fix -> single once the sky is clear for this long [s]
  double float_acquire_s = 3.0;   ///< single -> float (corrections arrive) [s]
  double fixed_acquire_s = 10.0;  ///< float -> fixed (ambiguities resolved) [s]
  std::vector<GnssOutage> outages;
  std::vector<GnssZone> zones;
  uint64_t seed = 1;

  /// The problems of these parameters, empty when usable ("rate_hz: 0 is not > 0").
  std::vector<std::string> validate() const;
};

/// One epoch of the receiver's output.
struct GnssSolution {
  double time_s = 0.0;  ///< model time of the epoch [s]
  double utc_s = 0.0;   ///< UTC of the epoch (Unix seconds)
  GnssFixState state = GnssFixState::kNoFix;
  Eigen::Vector3d enu_m = Eigen::Vector3d::Zero();  ///< reported position in the local frame [m] (truth + error)
  double latitude_deg = 0.0;                        ///< reported position, WGS84
  double longitude_deg = 0.0;
  double altitude_m = 0.0;  ///< ellipsoidal height [m]
  /// The receiver's own 1-sigma estimate of its east, north, up error [m] (the state's profile); GST carries it.
  Eigen::Vector3d sigma_m = Eigen::Vector3d::Zero();
  double speed_mps = 0.0;   ///< horizontal speed over ground [m/s]
  double course_deg = 0.0;  ///< course over ground, clockwise from true north [deg, 0..360)
  int satellites = 0;
  double hdop = 99.99;
};

/// Local tangent plane around a WGS84 datum: east/north [m] to latitude/longitude [deg] with the ellipsoid's radii
/// of curvature at the datum (error under 1 mm within 1 km of it), up added to the height.
struct GeodeticDatum {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;

  /// (latitude [deg], longitude [deg], ellipsoidal height [m]) of an east-north-up point [m].
  Eigen::Vector3d toGeodetic(const Eigen::Vector3d& enu_m) const;
  /// The inverse of toGeodetic.
  Eigen::Vector3d toEnu(double latitude_deg, double longitude_deg, double altitude_m) const;
};

/// The receiver. Feed it the antenna's true position at any rate; it answers with a solution at each epoch
/// (every 1 / rate_hz of model time). Deterministic for a seed.
class GnssModel {
 public:
  /// Throws std::invalid_argument listing the problems of `params` (validate()).
  explicit GnssModel(GnssModelParams params);

  /// The solution of the epoch due at `time_s` [s], or nothing between epochs. Time must not go back.
  std::optional<GnssSolution> update(double time_s, const Eigen::Vector3d& true_enu_m);

  /// The best state the sky allows at this place and time (outages and zones), before acquisition delays.
  GnssFixState availableState(double time_s, const Eigen::Vector3d& true_enu_m) const;

  GnssFixState state() const { return state_; }
  const GnssModelParams& params() const { return params_; }

 private:
  GnssSolution epoch(double time_s, const Eigen::Vector3d& true_enu_m);
  void stepState(double time_s, GnssFixState available);
  void stepErrors(double dt_s);
  const GnssStateProfile& profile(GnssFixState state) const;

  GnssModelParams params_;
  GeodeticDatum datum_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
  GnssFixState state_ = GnssFixState::kNoFix;
  bool climbing_ = false;       ///< a better state than the current one is available
  double state_since_s_ = 0.0;  ///< when the current climb step began (a better state became available) [s]
  /// One Gauss-Markov error per fix state (single, float, fixed), all running, so a state's error is stationary.
  std::array<Eigen::Vector3d, 3> errors_m_;
  std::optional<double> last_epoch_s_;
  std::optional<Eigen::Vector3d> last_true_enu_m_;
  long next_epoch_ = 0;
};

}  // namespace thorvald_sim
