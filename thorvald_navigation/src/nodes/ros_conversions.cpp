#include "ros_conversions.h"

#include <cmath>

namespace thorvald_navigation {

std::string scanToPoints(const sensor_msgs::LaserScan& scan, const thorvald_base::Pose2D& sensor_in_base,
                         double max_range, ScanPoints* out) {
  out->hits.clear();
  out->free_ends.clear();
  out->dropped = 0;
  if (!std::isfinite(scan.angle_min) || !std::isfinite(scan.angle_increment) || scan.angle_increment == 0.0f)
    return "angle_min and angle_increment must be finite and angle_increment != 0";
  if (scan.ranges.size() > 100000) return "more than 100000 beams";
  if (!std::isfinite(scan.range_max) || !(scan.range_max > 0.0f)) return "range_max must be > 0";
  const double limit = std::min<double>(scan.range_max, max_range);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    const double a = scan.angle_min + static_cast<double>(i) * scan.angle_increment;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    if (std::isinf(r) && r > 0.0) {  // REP 117: +inf means nothing within range
      out->free_ends.push_back(sensor_in_base.transformPoint(dir * limit));
    } else if (!std::isfinite(r) || r < scan.range_min) {
      ++out->dropped;
    } else if (r >= limit) {
      out->free_ends.push_back(sensor_in_base.transformPoint(dir * limit));
    } else {
      out->hits.push_back(sensor_in_base.transformPoint(dir * r));
    }
  }
  return {};
}

}  // namespace thorvald_navigation
