#pragma once

#include <optional>

namespace thorvald_navigation {

/// A point in the Universal Transverse Mercator grid (WGS84).
struct UtmPoint {
  double easting = 0.0;   ///< [m], 500 000 on the zone's central meridian
  double northing = 0.0;  ///< [m], from the equator; + 10 000 000 in the southern hemisphere
  int zone = 0;           ///< 1 ... 60
  bool north = true;      ///< hemisphere: false adds the 10 000 000 m false northing
  char band = 'N';        ///< latitude band letter C ... X (I and O left out)
};

/// The UTM zone of a position, with Norway's (32V) and Svalbard's (31X, 33X, 35X, 37X) exceptions; longitude
/// 180 deg is zone 60. `lat_deg`, `lon_deg` in degrees; nothing outside UTM's latitudes [-80, 84] deg.
std::optional<int> utmZone(double lat_deg, double lon_deg);
/// Latitude band letter, 'C' (-80 deg) to 'X' (72 ... 84 deg); nothing outside [-80, 84] deg.
std::optional<char> utmBand(double lat_deg);
/// Longitude of a zone's central meridian [deg].
double utmCentralMeridian(int zone);

/// WGS84 latitude and longitude [deg] to UTM in the position's own zone (or in `force_zone` when given: the
/// datum's zone, so that a field across a zone edge keeps one grid). Transverse Mercator by Krueger's series to
/// the sixth order in n (well below a millimetre within a zone). Nothing for a latitude outside [-80, 84] deg,
/// a non-finite input or a zone outside 1 ... 60.
std::optional<UtmPoint> toUtm(double lat_deg, double lon_deg, std::optional<int> force_zone = std::nullopt);

/// Latitude and longitude [deg] of a UTM point.
struct LatLon {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
};
/// The inverse of toUtm; nothing for a zone outside 1 ... 60 or a non-finite input.
std::optional<LatLon> fromUtm(const UtmPoint& p);

/// The grid convergence at a position [rad]: the angle from true north to grid north (positive east of the
/// central meridian in the northern hemisphere).
double utmConvergence(double lat_deg, double lon_deg, int zone);

}  // namespace thorvald_navigation
