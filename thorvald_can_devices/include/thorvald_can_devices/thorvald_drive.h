#pragma once

#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/motor_drive.h"
#include "thorvald_can_devices/can_device.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"

namespace thorvald_can_devices {

/// Host side of one Thorvald drive controller (one node). A type-0 controller runs one drive (propulsion +
/// steering); a type-1 controller runs one or two propulsion drives, channel 1 and channel 2 (two consecutive
/// type-1 drives with the same node). Sends the command frames once every channel has been updated in a cycle,
/// keeps the sequence counter, decodes feedback, status flags, info and heartbeat, and restarts a node that
/// reports boot-up or pre-operational.
class ThorvaldController : public CanDevice {
 public:
  /// `channels`: the robot-file entries of the drives on this node (1 for type 0; 1 or 2 for type 1).
  ThorvaldController(CanBus* bus, std::vector<thorvald_base::DriveConfig> channels);

  std::string label() const override;
  std::vector<uint32_t> receiveIds() const override;
  std::vector<uint32_t> transmitIds() const override;
  void start(double now_s) override;
  void handle(const CanFrame& frame, double now_s) override;
  void tick(double now_s) override;
  bool operational() const override;
  unsigned long malformed() const override { return malformed_; }

  int node() const { return node_; }
  size_t channels() const { return channels_.size(); }
  void setCommand(size_t channel, const thorvald_base::DriveCommand& command) { commands_[channel] = command; }
  /// Marks `channel` updated at now_s; sends the command frames when every channel is.
  void channelUpdated(size_t channel, double now_s);
  thorvald_base::DriveFeedback feedback(size_t channel) const { return feedback_[channel]; }
  thorvald_base::DriveStatus status(size_t channel) const;
  void reconfigure(size_t channel, const thorvald_base::DriveConfig& config) { channels_[channel] = config; }
  bool startHoming();
  void clearFault();
  int32_t sequence() const { return sequence_; }
  /// A drive whose feedback frames stop for this long is lost (it may still send heartbeats) [s].
  void setFeedbackTimeout(double timeout_s) { feedback_timeout_s_ = timeout_s; }
  const ThorvaldStatus& lastStatus() const { return status_frame_; }

 private:
  void sendCommands();
  void onFeedback(const ThorvaldFeedback& fb, double now_s);
  void onInfo(const ThorvaldInfo& info);

  CanBus* bus_;
  std::vector<thorvald_base::DriveConfig> channels_;
  int node_ = 0;
  int type_ = 0;
  std::vector<thorvald_base::DriveCommand> commands_;
  std::vector<double> updated_at_;
  std::vector<thorvald_base::DriveFeedback> feedback_;
  int32_t sequence_ = 0;
  double now_s_ = 0.0;
  double last_heartbeat_s_ = -1e9;
  double last_feedback_s_ = -1e9;
  double last_start_sent_s_ = -1e9;
  double operational_since_s_ = -1e9;
  double feedback_timeout_s_ = 0.06;
  static constexpr double kFirstFeedbackS = 0.5;  ///< for the first feedback after becoming operational [s]
  uint8_t nmt_state_ = kHeartbeatBootUp;
  bool heard_ = false;
  bool status_seen_ = false;
  ThorvaldStatus status_frame_;
  bool homing_ = false;
  std::string config_fault_;  ///< controller type or encoder ppr differ from the robot file
  unsigned long malformed_ = 0;
};

/// One drive of the robot file on a ThorvaldController channel: what base_driver sees (MotorDrive).
class ThorvaldDrive : public thorvald_base::MotorDrive {
 public:
  ThorvaldDrive(std::shared_ptr<ThorvaldController> controller, size_t channel)
      : controller_(std::move(controller)), channel_(channel) {}
  void setCommand(const thorvald_base::DriveCommand& command) override { controller_->setCommand(channel_, command); }
  void update(double now_s) override;
  thorvald_base::DriveFeedback feedback() const override { return controller_->feedback(channel_); }
  thorvald_base::DriveStatus status() const override { return controller_->status(channel_); }
  void reconfigure(const thorvald_base::DriveConfig& config) override { controller_->reconfigure(channel_, config); }
  bool startHoming() override { return channel_ == 0 && controller_->startHoming(); }
  void clearFault() override { controller_->clearFault(); }

 private:
  std::shared_ptr<ThorvaldController> controller_;
  size_t channel_;
  double last_update_s_ = -1.0;
};

}  // namespace thorvald_can_devices
