#include "greenhouse_rail_nav/mount_calibration.h"

#include <cmath>
#include <fstream>

#include <yaml-cpp/yaml.h>

namespace greenhouse_rail_nav {

bool computeMountCorrection(const thorvald_base::Pose2D& rail_in_base_uncorrected, double max_y_m, double max_yaw_rad,
                            MountCorrection* correction, std::string* error) {
  const thorvald_base::Pose2D& seen = rail_in_base_uncorrected;
  if (!std::isfinite(seen.x) || !std::isfinite(seen.y) || !std::isfinite(seen.yaw)) {
    *error = "rail frame is not finite";
    return false;
  }
  // Rotating by -yaw makes the rails point straight ahead; the centre line's remaining sideways offset
  // (the same for every point on it) is what the shift must cancel.
  const double yaw = thorvald_base::normalizeAngle(-seen.yaw);
  const double offset = std::sin(yaw) * seen.x + std::cos(yaw) * seen.y;
  if (std::abs(seen.yaw) > max_yaw_rad || std::abs(offset) > max_y_m) {
    *error = "rails seen at yaw " + std::to_string(seen.yaw) + " rad, offset " + std::to_string(offset) +
             " m: beyond the limits (" + std::to_string(max_yaw_rad) + " rad, " + std::to_string(max_y_m) +
             " m) for a robot standing on the rails";
    return false;
  }
  correction->yaw_rad = yaw;
  correction->y_m = -offset;
  return true;
}

bool saveMountCorrection(const MountCorrection& correction, const std::string& path, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot write " + path;
    return false;
  }
  out.precision(9);
  out << "# Camera mount correction of greenhouse_rail_nav/rail_detector, measured on the rails.\n"
      << "y_m: " << correction.y_m << "\nyaw_rad: " << correction.yaw_rad << "\n";
  return static_cast<bool>(out);
}

bool loadMountCorrection(const std::string& path, MountCorrection* correction, std::string* error) {
  try {
    const YAML::Node doc = YAML::LoadFile(path);
    MountCorrection c;
    c.y_m = doc["y_m"].as<double>();
    c.yaw_rad = doc["yaw_rad"].as<double>();
    if (!std::isfinite(c.y_m) || !std::isfinite(c.yaw_rad)) {
      *error = path + ": y_m and yaw_rad must be finite";
      return false;
    }
    *correction = c;
    return true;
  } catch (const YAML::Exception& e) {
    *error = path + ": expected y_m [m] and yaw_rad [rad]: " + e.what();
    return false;
  }
}

}  // namespace greenhouse_rail_nav
