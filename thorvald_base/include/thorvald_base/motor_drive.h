#pragma once

#include "thorvald_base/drive_state.h"
#include "thorvald_base/robot_config.h"

namespace thorvald_base {

/// One drive module as base_driver uses it, whatever it is: a simulated joint pair or a motor controller on a
/// bus. base_driver calls setCommand, then update, then reads feedback and status, once per control cycle,
/// from one thread. Implementations that receive from another thread guard their own state.
class MotorDrive {
 public:
  virtual ~MotorDrive() = default;

  /// The latest wanted wheel speed and steering angle. Sent or applied on the next update.
  virtual void setCommand(const DriveCommand& command) = 0;

  /// Advances the drive to time `now_s` [s]: a simulator integrates, a device sends its command frames.
  virtual void update(double now_s) = 0;

  /// Latest measured joint state (valid == false until the first reading).
  virtual DriveFeedback feedback() const = 0;

  /// Online / fault state. A drive that is offline or faulted makes base_driver stop all propulsion.
  virtual DriveStatus status() const = 0;

  /// Takes changed drive keys (e.g. r_wheel) from the next update on.
  virtual void reconfigure(const DriveConfig& config) = 0;

  /// Starts steering homing. Returns false where the drive has no homing.
  virtual bool startHoming() { return false; }

  /// Asks the drive to leave a latched fault state (after the cause is gone).
  virtual void clearFault() {}
};

}  // namespace thorvald_base
