#include "thorvald_navigation/utm.h"

#include <array>
#include <cmath>

namespace thorvald_navigation {

namespace {

constexpr double kA = 6378137.0;             // WGS84 semi-major axis [m]
constexpr double kF = 1.0 / 298.257223563;   // WGS84 flattening
constexpr double kK0 = 0.9996;               // UTM scale on the central meridian
constexpr double kFalseEasting = 500000.0;   // [m]
constexpr double kFalseNorthingSouth = 1e7;  // [m]
constexpr double kDeg = M_PI / 180.0;

/// Krueger's series coefficients for WGS84, in the third flattening n.
struct Series {
  double a_rect;                // rectifying radius [m]
  std::array<double, 6> alpha;  // forward
  std::array<double, 6> beta;   // inverse
  double e;                     // first eccentricity
};

const Series& series() {
  static const Series s = [] {
    const double n = kF / (2.0 - kF);
    const double n2 = n * n, n3 = n2 * n, n4 = n3 * n, n5 = n4 * n, n6 = n5 * n;
    Series r;
    r.a_rect = kA / (1.0 + n) * (1.0 + n2 / 4.0 + n4 / 64.0 + n6 / 256.0);
    r.alpha = {
        n / 2.0 - 2.0 * n2 / 3.0 + 5.0 * n3 / 16.0 + 41.0 * n4 / 180.0 - 127.0 * n5 / 288.0 + 7891.0 * n6 / 37800.0,
        13.0 * n2 / 48.0 - 3.0 * n3 / 5.0 + 557.0 * n4 / 1440.0 + 281.0 * n5 / 630.0 - 1983433.0 * n6 / 1935360.0,
        61.0 * n3 / 240.0 - 103.0 * n4 / 140.0 + 15061.0 * n5 / 26880.0 + 167603.0 * n6 / 181440.0,
        49561.0 * n4 / 161280.0 - 179.0 * n5 / 168.0 + 6601661.0 * n6 / 7257600.0,
        34729.0 * n5 / 80640.0 - 3418889.0 * n6 / 1995840.0,
        212378941.0 * n6 / 319334400.0};
    r.beta = {n / 2.0 - 2.0 * n2 / 3.0 + 37.0 * n3 / 96.0 - n4 / 360.0 - 81.0 * n5 / 512.0 + 96199.0 * n6 / 604800.0,
              n2 / 48.0 + n3 / 15.0 - 437.0 * n4 / 1440.0 + 46.0 * n5 / 105.0 - 1118711.0 * n6 / 3870720.0,
              17.0 * n3 / 480.0 - 37.0 * n4 / 840.0 - 209.0 * n5 / 4480.0 + 5569.0 * n6 / 90720.0,
              4397.0 * n4 / 161280.0 - 11.0 * n5 / 504.0 - 830251.0 * n6 / 7257600.0,
              4583.0 * n5 / 161280.0 - 108847.0 * n6 / 3991680.0,
              20648693.0 * n6 / 638668800.0};
    r.e = std::sqrt(kF * (2.0 - kF));
    return r;
  }();
  return s;
}

/// Conformal latitude's tangent from the geodetic latitude.
double conformalTan(double phi, double e) {
  const double t = std::tan(phi);
  const double sigma = std::sinh(e * std::atanh(e * t / std::sqrt(1.0 + t * t)));
  return t * std::sqrt(1.0 + sigma * sigma) - sigma * std::sqrt(1.0 + t * t);
}

/// Geodetic latitude's tangent from the conformal one (Newton's method on conformalTan).
double geodeticTan(double tau_prime, double e) {
  double tau = tau_prime;
  for (int i = 0; i < 8; ++i) {
    const double sigma = std::sinh(e * std::atanh(e * tau / std::sqrt(1.0 + tau * tau)));
    const double tp = tau * std::sqrt(1.0 + sigma * sigma) - sigma * std::sqrt(1.0 + tau * tau);
    const double dtau = (tau_prime - tp) / std::sqrt(1.0 + tp * tp) * (1.0 + (1.0 - e * e) * tau * tau) /
                        ((1.0 - e * e) * std::sqrt(1.0 + tau * tau));
    tau += dtau;
    if (std::abs(dtau) < 1e-14) break;
  }
  return tau;
}

}  // namespace

std::optional<int> utmZone(double lat_deg, double lon_deg) {
  if (!std::isfinite(lat_deg) || !std::isfinite(lon_deg) || lat_deg < -80.0 || lat_deg > 84.0) return std::nullopt;
  double lon = std::fmod(lon_deg + 180.0, 360.0);
  if (lon < 0.0) lon += 360.0;
  lon -= 180.0;  // [-180, 180)
  if (lon_deg == 180.0) return 60;
  int zone = static_cast<int>(std::floor((lon + 180.0) / 6.0)) + 1;
  if (lat_deg >= 56.0 && lat_deg < 64.0 && lon >= 3.0 && lon < 12.0) zone = 32;  // south-west Norway
  if (lat_deg >= 72.0 && lon >= 0.0 && lon < 42.0) {                             // Svalbard
    if (lon < 9.0)
      zone = 31;
    else if (lon < 21.0)
      zone = 33;
    else if (lon < 33.0)
      zone = 35;
    else
      zone = 37;
  }
  return zone;
}

std::optional<char> utmBand(double lat_deg) {
  if (!std::isfinite(lat_deg) || lat_deg < -80.0 || lat_deg > 84.0) return std::nullopt;
  static const char kBands[] = "CDEFGHJKLMNPQRSTUVWX";
  const int i = std::min(19, static_cast<int>(std::floor((lat_deg + 80.0) / 8.0)));
  return kBands[i];
}

double utmCentralMeridian(int zone) { return -183.0 + 6.0 * zone; }

std::optional<UtmPoint> toUtm(double lat_deg, double lon_deg, std::optional<int> force_zone) {
  const std::optional<int> own = utmZone(lat_deg, lon_deg);
  if (!own) return std::nullopt;
  const int zone = force_zone ? *force_zone : *own;
  if (zone < 1 || zone > 60) return std::nullopt;
  const Series& s = series();
  const double phi = lat_deg * kDeg;
  const double lambda = std::remainder(lon_deg - utmCentralMeridian(zone), 360.0) * kDeg;
  const double tau_p = conformalTan(phi, s.e);
  const double xi_p = std::atan2(tau_p, std::cos(lambda));
  const double eta_p = std::asinh(std::sin(lambda) / std::hypot(tau_p, std::cos(lambda)));
  double xi = xi_p, eta = eta_p;
  for (int j = 1; j <= 6; ++j) {
    xi += s.alpha[j - 1] * std::sin(2.0 * j * xi_p) * std::cosh(2.0 * j * eta_p);
    eta += s.alpha[j - 1] * std::cos(2.0 * j * xi_p) * std::sinh(2.0 * j * eta_p);
  }
  UtmPoint p;
  p.zone = zone;
  p.north = lat_deg >= 0.0;
  p.band = *utmBand(lat_deg);
  p.easting = kFalseEasting + kK0 * s.a_rect * eta;
  p.northing = kK0 * s.a_rect * xi + (p.north ? 0.0 : kFalseNorthingSouth);
  return p;
}

std::optional<LatLon> fromUtm(const UtmPoint& p) {
  if (p.zone < 1 || p.zone > 60 || !std::isfinite(p.easting) || !std::isfinite(p.northing)) return std::nullopt;
  const Series& s = series();
  const double xi = (p.northing - (p.north ? 0.0 : kFalseNorthingSouth)) / (kK0 * s.a_rect);
  const double eta = (p.easting - kFalseEasting) / (kK0 * s.a_rect);
  double xi_p = xi, eta_p = eta;
  for (int j = 1; j <= 6; ++j) {
    xi_p -= s.beta[j - 1] * std::sin(2.0 * j * xi) * std::cosh(2.0 * j * eta);
    eta_p -= s.beta[j - 1] * std::cos(2.0 * j * xi) * std::sinh(2.0 * j * eta);
  }
  const double sinh_eta = std::sinh(eta_p), cos_xi = std::cos(xi_p);
  const double tau_p = std::sin(xi_p) / std::hypot(sinh_eta, cos_xi);
  const double tau = geodeticTan(tau_p, s.e);
  LatLon out;
  out.lat_deg = std::atan(tau) / kDeg;
  out.lon_deg = std::remainder(utmCentralMeridian(p.zone) + std::atan2(sinh_eta, cos_xi) / kDeg, 360.0);
  return out;
}

double utmConvergence(double lat_deg, double lon_deg, int zone) {
  // First-order spherical form; enough to turn a heading into grid terms (< 0.01 deg error inside a zone).
  const double dl = std::remainder(lon_deg - utmCentralMeridian(zone), 360.0) * kDeg;
  return std::atan(std::tan(dl) * std::sin(lat_deg * kDeg));
}

}  // namespace thorvald_navigation
