#pragma once

#include <string>

#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// Camera mount correction (paper §V-C): with the robot standing on the rails, aligned and centred, the
/// rails must appear straight ahead (zero y, zero yaw). What is seen instead is the mount error; the
/// correction is the planar transform that maps what the camera sees in base_link onto the truth.
struct MountCorrection {
  double y_m = 0.0;      ///< sideways shift [m]
  double yaw_rad = 0.0;  ///< rotation about z [rad]

  /// As a transform applied to everything seen in base_link.
  thorvald_base::Pose2D asTransform() const { return thorvald_base::Pose2D(0.0, y_m, yaw_rad); }
};

/// Computes the correction from the rail frame seen in base_link (without any correction) while the
/// robot stands on the rails. Refuses (false, *error says why) when the view is too far from straight
/// for the robot to be on the rails (|yaw| > max_yaw_rad or centre line |y| > max_y_m) or not finite.
bool computeMountCorrection(const thorvald_base::Pose2D& rail_in_base_uncorrected, double max_y_m, double max_yaw_rad,
                            MountCorrection* correction, std::string* error);

bool saveMountCorrection(const MountCorrection& correction, const std::string& path, std::string* error);
/// Reads a file written by saveMountCorrection; a missing file is an error (callers decide if it matters).
bool loadMountCorrection(const std::string& path, MountCorrection* correction, std::string* error);

}  // namespace greenhouse_rail_nav
