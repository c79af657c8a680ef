#pragma once

// The `datasheet` error model of a planar scanning lidar (Hokuyo UTM-30LX), applied to the beams' true ranges and
// incidence angles. ROS-free and deterministic given the random engine.

#include <random>
#include <vector>

namespace thorvald_sim {

/// Range errors of the Hokuyo UTM-30LX (figures and sources: README, "Sensor models and realism").
struct LidarModel {
  double sigma_near_m = 0.010;      ///< range noise std dev up to near_limit_m [m] (repeatability)
  double sigma_far_m = 0.025;       ///< range noise std dev beyond near_limit_m [m]
  double near_limit_m = 10.0;       ///< [m]
  double max_incidence_rad = 1.53;  ///< no return where the beam meets the surface more obliquely than this [rad]
  /// Received power falls as reflectance * cos(incidence) / range^2 (a matte surface): no return where that is below
  /// the power from a white sheet at white_range_m met head-on, reflectance * cos(incidence) < (range/white_range)^2.
  double white_range_m = 30.0;     ///< detection range on the datasheet's white sheet at normal incidence [m]
  double reflectance = 1.0;        ///< the surfaces' reflectance relative to that sheet
  double dropout = 0.001;          ///< probability that a beam with a target returns nothing
  double edge_jump_m = 0.10;       ///< range step between neighbouring beams taken as an edge [m]
  double mixed_probability = 0.5;  ///< probability that a beam beside an edge returns a mixed pixel
  double sweep_s = 0.025;          ///< one mirror turn (360 deg) [s]: beams are taken at successive times
};

/// What one beam meets: its true range (negative for nothing) and the angle between the beam and the surface
/// normal [rad].
struct LidarBeam {
  double range_m = -1.0;
  double incidence_rad = 0.0;
};

/// Range noise std dev at `range_m` [m].
double lidarSigma(const LidarModel& model, double range_m);

/// Whether a beam meeting a surface at `range_m` [m] and `incidence_rad` returns (before dropouts): incidence up to
/// max_incidence_rad and reflectance * cos(incidence) >= (range / white_range)^2.
bool lidarReturns(const LidarModel& model, double range_m, double incidence_rad);

/// The scan the device reports for the true beams: +inf where there is no return (nothing hit, out of
/// [range_min, range_max], incidence beyond max_incidence or too glancing for the range (lidarReturns), dropout). A
/// beam whose neighbour's range differs by more than edge_jump_m straddles the edge: with mixed_probability the nearer
/// beam of the pair returns a range between the two surfaces (uniform). Then Gaussian noise of lidarSigma.
std::vector<float> applyLidarModel(const std::vector<LidarBeam>& beams, double range_min_m, double range_max_m,
                                   const LidarModel& model, std::mt19937& rng);

}  // namespace thorvald_sim
