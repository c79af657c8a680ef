#pragma once

#include <string>
#include <vector>

#include "thorvald_base/battery.h"
#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/battery_protocol.h"
#include "thorvald_can_devices/can_device.h"

namespace thorvald_can_devices {

/// Host side of a Thorvald battery enclosure: listens to its three broadcast frames (it is never sent to) and
/// keeps the latest reading. Offline when no frame came for 2 s.
class ThorvaldBattery : public CanDevice, public thorvald_base::Battery {
 public:
  explicit ThorvaldBattery(const thorvald_base::BatteryConfig& config);

  // CanDevice
  std::string label() const override { return name_ + " (battery id " + std::to_string(id_) + ")"; }
  std::vector<uint32_t> receiveIds() const override;
  std::vector<uint32_t> transmitIds() const override { return {}; }
  void start(double) override {}
  void handle(const CanFrame& frame, double now_s) override;
  void tick(double now_s) override { now_s_ = now_s; }
  bool operational() const override { return heard_ && now_s_ - last_frame_s_ <= kHeartbeatTimeoutS; }
  unsigned long malformed() const override { return malformed_; }

  // thorvald_base::Battery
  const std::string& name() const override { return name_; }
  void update(double) override {}
  thorvald_base::BatteryReading reading() const override;

 private:
  std::string name_;
  int id_;
  double now_s_ = 0.0, last_frame_s_ = -1e9;
  bool heard_ = false;
  thorvald_base::BatteryReading reading_;
  unsigned long malformed_ = 0;
};

}  // namespace thorvald_can_devices
