#pragma once

#include <map>
#include <string>

#include <ros/time.h>
#include <tf2_ros/buffer.h>

#include "thorvald_base/pose2d.h"

namespace thorvald_navigation {

/// Looks up planar transforms on tf, caching the fixed sensor mounts (a lidar does not move on base_link).
class FrameLookup {
 public:
  explicit FrameLookup(const tf2_ros::Buffer& buffer) : buffer_(buffer) {}
  /// Pose of `child` in `parent` at `stamp`; false with `error` set when tf cannot say.
  bool lookup(const std::string& parent, const std::string& child, const ros::Time& stamp, double timeout_s,
              thorvald_base::Pose2D* pose, std::string* error) const;
  /// Like lookup(), latest available, remembered for `child` once found.
  bool mount(const std::string& parent, const std::string& child, thorvald_base::Pose2D* pose, std::string* error);

 private:
  const tf2_ros::Buffer& buffer_;
  std::map<std::string, thorvald_base::Pose2D> mounts_;
};

}  // namespace thorvald_navigation
