#pragma once

namespace thorvald_teleop {

/// A body-frame velocity command: what a geometry_msgs/Twist carries, without ROS.
struct VelocityCommand {
  double linear_x = 0.0;   ///< [m/s] forward
  double linear_y = 0.0;   ///< [m/s] left
  double linear_z = 0.0;   ///< [m/s] up
  double angular_x = 0.0;  ///< [rad/s] roll rate
  double angular_y = 0.0;  ///< [rad/s] pitch rate
  double angular_z = 0.0;  ///< [rad/s] yaw rate, counter-clockwise

  bool isZero() const {
    return linear_x == 0.0 && linear_y == 0.0 && linear_z == 0.0 && angular_x == 0.0 && angular_y == 0.0 &&
           angular_z == 0.0;
  }
  VelocityCommand scaled(double gain) const {
    return {linear_x * gain, linear_y * gain, linear_z * gain, angular_x * gain, angular_y * gain, angular_z * gain};
  }
};

}  // namespace thorvald_teleop
