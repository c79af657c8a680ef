#include "scan_frames.h"

#include <geometry_msgs/TransformStamped.h>
#include <tf2/exceptions.h>

#include "ros_conversions.h"

namespace thorvald_navigation {

bool FrameLookup::lookup(const std::string& parent, const std::string& child, const ros::Time& stamp, double timeout_s,
                         thorvald_base::Pose2D* pose, std::string* error) const {
  try {
    const geometry_msgs::TransformStamped t = buffer_.lookupTransform(parent, child, stamp, ros::Duration(timeout_s));
    *pose = thorvald_map::fromTransform(t.transform);
    if (!pose->finite()) {
      *error = "transform " + parent + " -> " + child + " is not finite";
      return false;
    }
    return true;
  } catch (const tf2::TransformException& e) {
    *error = e.what();
    return false;
  }
}

bool FrameLookup::mount(const std::string& parent, const std::string& child, thorvald_base::Pose2D* pose,
                        std::string* error) {
  const auto it = mounts_.find(child);
  if (it != mounts_.end()) {
    *pose = it->second;
    return true;
  }
  if (!lookup(parent, child, ros::Time(0), 0.0, pose, error)) return false;
  mounts_[child] = *pose;
  return true;
}

}  // namespace thorvald_navigation
