#include "thorvald_sim/gnss_model.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace thorvald_sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr double kWgs84A = 6378137.0;          // semi-major axis [m]
constexpr double kWgs84E2 = 6.69437999014e-3;  // first eccentricity squared
constexpr double kEpochSlack = 1e-9;           // [s] an epoch due at t is taken at t - slack too

/// Radii of curvature (meridian, prime vertical) [m] at `latitude_deg`.
std::pair<double, double> radiiOfCurvature(double latitude_deg) {
  const double s = std::sin(latitude_deg / kDegPerRad);
  const double w = std::sqrt(1.0 - kWgs84E2 * s * s);
  return {kWgs84A * (1.0 - kWgs84E2) / (w * w * w), kWgs84A / w};
}

void checkProfile(const char* name, const GnssStateProfile& p, std::vector<std::string>& problems) {
  const auto bad = [&](const char* key, double v, const char* expected) {
    std::ostringstream s;
    s << name << "." << key << ": " << v << " is not " << expected;
    problems.push_back(s.str());
  };
  if (!(p.sigma_horizontal_m > 0.0)) bad("sigma_horizontal_m", p.sigma_horizontal_m, "> 0");
  if (!(p.sigma_vertical_m > 0.0)) bad("sigma_vertical_m", p.sigma_vertical_m, "> 0");
  if (!(p.correlation_time_s > 0.0)) bad("correlation_time_s", p.correlation_time_s, "> 0");
  if (p.satellites < 4 || p.satellites > 99) bad("satellites", p.satellites, "within [4, 99]");
  if (!(p.hdop > 0.0 && p.hdop < 100.0)) bad("hdop", p.hdop, "within (0, 100)");
}

}  // namespace

const char* gnssFixStateName(GnssFixState state) {
  switch (state) {
    case GnssFixState::kNoFix:
      return "no fix";
    case GnssFixState::kSingle:
      return "single";
    case GnssFixState::kFloat:
      return "float";
    case GnssFixState::kFixed:
      return "fixed";
  }
  return "?";
}

std::vector<std::string> GnssModelParams::validate() const {
  std::vector<std::string> problems;
  const auto bad = [&](const std::string& what) { problems.push_back(what); };
  if (!(rate_hz > 0.0 && rate_hz <= 100.0)) bad("rate_hz: " + std::to_string(rate_hz) + " is not within (0, 100]");
  if (!(std::abs(datum_latitude_deg) < 89.0)) bad("datum_latitude_deg: not within (-89, 89)");
  if (!(std::abs(datum_longitude_deg) <= 180.0)) bad("datum_longitude_deg: not within [-180, 180]");
  if (!std::isfinite(datum_altitude_m)) bad("datum_altitude_m: not finite");
  if (!(utc_start_s >= 0.0 && utc_start_s < 4.0e9)) bad("utc_start_s: not within [0, 4e9)");
  checkProfile("fixed", fixed, problems);
  checkProfile("floating", floating, problems);
  checkProfile("single", single, problems);
  for (const double t : {single_acquire_s, float_acquire_s, fixed_acquire_s}) {
    if (!(t >= 0.0 && std::isfinite(t))) bad("acquisition times: " + std::to_string(t) + " is not >= 0");
  }
  for (size_t i = 0; i < outages.size(); ++i) {
    if (!(outages[i].end_s > outages[i].start_s)) bad("outages[" + std::to_string(i) + "]: end_s is not > start_s");
  }
  for (size_t i = 0; i < zones.size(); ++i) {
    if (!(zones[i].radius_m > 0.0)) bad("zones[" + std::to_string(i) + "].radius_m: not > 0");
    if (zones[i].best_state == GnssFixState::kFixed)
      bad("zones[" + std::to_string(i) + "].best_state: fixed caps nothing");
  }
  return problems;
}

Eigen::Vector3d GeodeticDatum::toGeodetic(const Eigen::Vector3d& enu_m) const {
  const auto [meridian, prime] = radiiOfCurvature(latitude_deg);
  const double lat = latitude_deg + enu_m.y() / (meridian + altitude_m) * kDegPerRad;
  const double lon =
      longitude_deg + enu_m.x() / ((prime + altitude_m) * std::cos(latitude_deg / kDegPerRad)) * kDegPerRad;
  return {lat, lon, altitude_m + enu_m.z()};
}

Eigen::Vector3d GeodeticDatum::toEnu(double lat_deg, double lon_deg, double alt_m) const {
  const auto [meridian, prime] = radiiOfCurvature(latitude_deg);
  const double north = (lat_deg - latitude_deg) / kDegPerRad * (meridian + altitude_m);
  const double east =
      (lon_deg - longitude_deg) / kDegPerRad * (prime + altitude_m) * std::cos(latitude_deg / kDegPerRad);
  return {east, north, alt_m - altitude_m};
}

GnssModel::GnssModel(GnssModelParams params)
    : params_(std::move(params)),
      datum_{params_.datum_latitude_deg, params_.datum_longitude_deg, params_.datum_altitude_m},
      rng_(params_.seed) {
  const auto problems = params_.validate();
  if (!problems.empty()) {
    std::string text = "GnssModel: ";
    for (size_t i = 0; i < problems.size(); ++i) text += (i ? "; " : "") + problems[i];
    throw std::invalid_argument(text);
  }
  // Each state's error starts from its stationary distribution, so its statistics hold from the first epoch.
  for (int s = 0; s < 3; ++s) {
    const GnssStateProfile& p = profile(static_cast<GnssFixState>(s + 1));
    errors_m_[s] = {p.sigma_horizontal_m * unit_normal_(rng_), p.sigma_horizontal_m * unit_normal_(rng_),
                    p.sigma_vertical_m * unit_normal_(rng_)};
  }
}

const GnssStateProfile& GnssModel::profile(GnssFixState state) const {
  switch (state) {
    case GnssFixState::kFixed:
      return params_.fixed;
    case GnssFixState::kFloat:
      return params_.floating;
    default:
      return params_.single;
  }
}

GnssFixState GnssModel::availableState(double time_s, const Eigen::Vector3d& true_enu_m) const {
  for (const GnssOutage& o : params_.outages) {
    if (time_s >= o.start_s && time_s < o.end_s) return GnssFixState::kNoFix;
  }
  GnssFixState best = GnssFixState::kFixed;
  for (const GnssZone& z : params_.zones) {
    const double d = std::hypot(true_enu_m.x() - z.east_m, true_enu_m.y() - z.north_m);
    if (d <= z.radius_m && z.best_state < best) best = z.best_state;
  }
  return best;
}

std::optional<GnssSolution> GnssModel::update(double time_s, const Eigen::Vector3d& true_enu_m) {
  if (last_epoch_s_ && time_s < *last_epoch_s_) {
    throw std::invalid_argument("GnssModel::update: time went back from " + std::to_string(*last_epoch_s_) + " to " +
                                std::to_string(time_s) + " s");
  }
  const double due_s = static_cast<double>(next_epoch_) / params_.rate_hz;
  if (time_s + kEpochSlack < due_s) return std::nullopt;
  // The epoch takes the latest epoch time not after `time_s` (a caller feeding slowly skips epochs).
  const long k = static_cast<long>(std::floor(time_s * params_.rate_hz + kEpochSlack));
  next_epoch_ = k + 1;
  return epoch(static_cast<double>(k) / params_.rate_hz, true_enu_m);
}

void GnssModel::stepState(double time_s, GnssFixState available) {
  if (available <= state_) {
    state_ = available;
    climbing_ = false;  // nothing better to acquire: the next climb counts from when it becomes possible
    return;
  }
  if (!climbing_) {
    climbing_ = true;
    state_since_s_ = time_s;
  }
  const GnssFixState next = static_cast<GnssFixState>(static_cast<int>(state_) + 1);
  const double needed_s = next == GnssFixState::kSingle  ? params_.single_acquire_s
                          : next == GnssFixState::kFloat ? params_.float_acquire_s
                                                         : params_.fixed_acquire_s;
  if (time_s - state_since_s_ + kEpochSlack >= needed_s) {
    state_ = next;
    state_since_s_ = time_s;
  }
}

void GnssModel::stepErrors(double dt_s) {
  for (int s = 0; s < 3; ++s) {
    const GnssStateProfile& p = profile(static_cast<GnssFixState>(s + 1));
    const double a = std::exp(-dt_s / p.correlation_time_s);
    const double b = std::sqrt(1.0 - a * a);  // keeps the variance stationary
    const Eigen::Vector3d sigma(p.sigma_horizontal_m, p.sigma_horizontal_m, p.sigma_vertical_m);
    for (int i = 0; i < 3; ++i) errors_m_[s][i] = a * errors_m_[s][i] + b * sigma[i] * unit_normal_(rng_);
  }
}

GnssSolution GnssModel::epoch(double time_s, const Eigen::Vector3d& true_enu_m) {
  if (last_epoch_s_) stepErrors(time_s - *last_epoch_s_);
  stepState(time_s, availableState(time_s, true_enu_m));
  GnssSolution sol;
  sol.time_s = time_s;
  sol.utc_s = params_.utc_start_s + time_s;
  sol.state = state_;
  if (last_epoch_s_ && last_true_enu_m_ && time_s > *last_epoch_s_) {
    const Eigen::Vector3d v = (true_enu_m - *last_true_enu_m_) / (time_s - *last_epoch_s_);
    sol.speed_mps = std::hypot(v.x(), v.y());
    const double course = std::atan2(v.x(), v.y()) * kDegPerRad;
    sol.course_deg = course < 0.0 ? course + 360.0 : course;
  }
  last_epoch_s_ = time_s;
  last_true_enu_m_ = true_enu_m;
  if (state_ == GnssFixState::kNoFix) return sol;
  const GnssStateProfile& p = profile(state_);
  sol.enu_m = true_enu_m + errors_m_[static_cast<int>(state_) - 1];
  const Eigen::Vector3d geo = datum_.toGeodetic(sol.enu_m);
  sol.latitude_deg = geo.x();
  sol.longitude_deg = geo.y();
  sol.altitude_m = geo.z();
  sol.sigma_m = {p.sigma_horizontal_m, p.sigma_horizontal_m, p.sigma_vertical_m};
  sol.satellites = p.satellites;
  sol.hdop = p.hdop;
  return sol;
}

}  // namespace thorvald_sim
