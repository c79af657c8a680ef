#include "thorvald_can_devices/thorvald_drive_sim.h"

#include <algorithm>
#include <cmath>

#include "sim_motion.h"
#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/drive_scaling.h"

namespace thorvald_can_devices {

ThorvaldDriveSim::ThorvaldDriveSim(std::vector<thorvald_base::DriveConfig> channels) : channels_(std::move(channels)) {
  node_ = channels_.front().node;
  type_ = channels_.front().type;
}

void ThorvaldDriveSim::reboot() {
  nmt_ = kHeartbeatBootUp;
  boot_sent_ = false;
  mode_ = ThorvaldMode::kDrive;
  command_[0] = command_[1] = 0;
  steering_command_ = ThorvaldScaling::steeringCommand(steering_rad_, channels_[0]);
  wheel_radps_[0] = wheel_radps_[1] = 0.0;
  last_command_s_ = -1e9;
}

void ThorvaldDriveSim::setFault(const std::string& fault, bool active) {
  if (fault == "silent") {
    if (faults_.silent && !active) reboot();
    faults_.silent = active;
  } else if (fault == "stall") {
    faults_.stall = active;
    if (active) latched_flags_ |= thorvald_flags::kStall;
  } else if (fault == "encoder") {
    faults_.encoder = active;
    if (active) latched_flags_ |= thorvald_flags::kPropulsionEncoderFault;
  }
}

void ThorvaldDriveSim::handle(const CanFrame& f, CanBus&) {
  if (faults_.silent || f.isError() || f.isExtended() || f.isRemote()) return;
  if (f.stdId() == canopen_ids::kNmt) {
    const auto m = decodeNmt(f);
    if (!forNode(m, node_)) return;
    if (const auto state = nmtStateAfter(m->command)) {
      nmt_ = *state;
    } else {
      reboot();
    }
    return;
  }
  const uint32_t id = f.stdId();
  const uint32_t n = static_cast<uint32_t>(node_);
  if (id != thorvald_ids::kCommand + n && id != thorvald_ids::kSetup + n && id != thorvald_ids::kMode + n &&
      id != thorvald_ids::kSteering + n)
    return;
  if (nmt_ != kHeartbeatOperational) return;
  const auto illegal = [&] {
    ++rejected_;
    latched_flags_ |= thorvald_flags::kIllegalCommand;
  };
  if (id == thorvald_ids::kCommand + n) {
    const auto c = decodeCommand(f);
    if (!c || std::abs(c->propulsion) > kThorvaldFullScale) return illegal();
    ++commands_received_;
    if (c->sequence == last_sequence_) return;  // a repeated frame: not a new command
    last_sequence_ = c->sequence;
    command_[0] = c->propulsion;
    last_command_s_ = now_s_;
  } else if (id == thorvald_ids::kSteering + n) {
    const auto s = decodeSteering(f);
    if (!s || std::abs(s->position) > kThorvaldFullScale || s->max_speed_rpm < 0) return illegal();
    if (type_ == 0) {
      steering_command_ = s->position;
      steering_max_rpm_ = s->max_speed_rpm;
    } else if (channels_.size() > 1) {
      command_[1] = s->position;
    }
  } else if (id == thorvald_ids::kMode + n) {
    const auto m = decodeMode(f);
    if (!m) return illegal();
    if (*m == ThorvaldMode::kHomeSteering && type_ == 0) {
      mode_ = *m;
      home_travel_rad_ = 0.0;
      homing_reported_done_ = false;
    } else if (*m != ThorvaldMode::kHomeSteering) {
      mode_ = *m;
    }
  } else if (id == thorvald_ids::kSetup + n) {
    const auto s = decodeSetup(f);
    if (!s) return illegal();
    if (s->setup_id == thorvald_setup::kFaultReset) {
      latched_flags_ = 0;
      if (faults_.stall) latched_flags_ |= thorvald_flags::kStall;
      if (faults_.encoder) latched_flags_ |= thorvald_flags::kPropulsionEncoderFault;
    } else if (s->setup_id == thorvald_setup::kCommandTimeoutMs && s->value > 0) {
      command_timeout_s_ = s->value / 1000.0;
    } else if (s->setup_id == thorvald_setup::kHeartbeatMs && s->value > 0) {
      heartbeat_period_s = s->value / 1000.0;
    } else {
      illegal();
    }
  }
}

void ThorvaldDriveSim::step(double now_s, CanBus& bus) {
  const double dt = now_s_ < 0.0 ? 0.0 : std::max(0.0, now_s - now_s_);
  now_s_ = now_s;
  if (faults_.silent) {
    wheel_radps_[0] = wheel_radps_[1] = 0.0;
    return;
  }
  if (nmt_ == kHeartbeatBootUp) {
    if (!boot_sent_) bus.send(encodeHeartbeat(node_, kHeartbeatBootUp));
    boot_sent_ = true;
    nmt_ = kHeartbeatPreOperational;
    next_heartbeat_s_ = now_s + heartbeat_period_s;
  }
  const bool running = nmt_ == kHeartbeatOperational;
  const bool blocked = (latched_flags_ & thorvald_flags::kFaultMask) != 0;
  stepPropulsion(now_s, dt, running, blocked);
  if (type_ == 0) stepSteering(dt, running, blocked);
  if (now_s >= next_heartbeat_s_) {
    bus.send(encodeHeartbeat(node_, nmt_));
    next_heartbeat_s_ = now_s + heartbeat_period_s;
  }
  if (!running) return;
  if (now_s >= next_tpdo_s_) {
    next_tpdo_s_ = now_s + tpdo_period_s;
    sendTpdos(bus);
  }
  if (now_s >= next_info_s_) {
    next_info_s_ = now_s + 0.5;
    sendInfo(bus);
  }
}

void ThorvaldDriveSim::stepPropulsion(double now_s, double dt, bool running, bool blocked) {
  const bool fresh = now_s - last_command_s_ <= command_timeout_s_;
  for (size_t c = 0; c < channels_.size(); ++c) {
    const auto& d = channels_[c];
    const bool drive = running && fresh && !blocked && mode_ != ThorvaldMode::kHomeSteering;
    const double target_rpm = drive ? ThorvaldScaling::motorRpmFromCommand(command_[c], d) : 0.0;
    const double target = ThorvaldScaling::wheelSpeedFromRpm(target_rpm, d);
    wheel_radps_[c] = faults_.stall ? 0.0 : approach(wheel_radps_[c], target, d.prp_sim_a / d.r_wheel * dt);
  }
}

void ThorvaldDriveSim::stepSteering(double dt, bool running, bool blocked) {
  const auto& d = channels_[0];
  double rate = d.str_sim_v;
  if (steering_max_rpm_ > 0) rate = std::min(rate, ThorvaldScaling::steeringSpeedFromRpm(steering_max_rpm_, d));
  double target = ThorvaldScaling::angleFromSteeringCommand(steering_command_, d);
  if (mode_ == ThorvaldMode::kHomeSteering) {
    target = 0.0;
    rate = 0.5 * d.str_sim_v;
  }
  if (!running || blocked) target = steering_rad_;
  const double before = steering_rad_;
  steering_rad_ = approach(steering_rad_, target, rate * dt);
  steering_radps_ = dt > 0 ? (steering_rad_ - before) / dt : 0.0;
  if (mode_ == ThorvaldMode::kHomeSteering) {
    home_travel_rad_ += std::fabs(steering_rad_ - before);
    if (home_travel_rad_ > 2.0 * M_PI) latched_flags_ |= thorvald_flags::kHomingExceeded;
    if (std::fabs(steering_rad_) < 1e-6) {
      mode_ = ThorvaldMode::kDrive;
      steering_command_ = 0;
    }
  }
}

void ThorvaldDriveSim::sendTpdos(CanBus& bus) {
  const auto& d0 = channels_[0];
  ThorvaldFeedback fb;
  const auto rpm = [&](size_t c) {
    return static_cast<int16_t>(
        clampToI32(ThorvaldScaling::rpmFromWheelSpeed(wheel_radps_[c], channels_[c]), -32768, 32767));
  };
  fb.propulsion_rpm = faults_.encoder ? 0 : rpm(0);
  if (type_ == 0) {
    fb.steering_rpm =
        static_cast<int16_t>(clampToI32(ThorvaldScaling::steeringRpmFromSpeed(steering_radps_, d0), -32768, 32767));
    fb.steering_count = ThorvaldScaling::countFromSteering(steering_rad_, d0);
  } else if (channels_.size() > 1) {
    fb.steering_rpm = rpm(1);
  }
  bus.send(encodeFeedback(node_, fb));
  ThorvaldPower p;
  for (size_t c = 0; c < channels_.size(); ++c) {
    p.power_permille[c] = static_cast<int16_t>(std::clamp(command_[c], -1000, 1000));
    p.current_da[c] = static_cast<int16_t>(std::fabs(wheel_radps_[c]) * 5.0);
  }
  bus.send(encodePower(node_, p));
  ThorvaldStatus st;
  st.flags = static_cast<uint8_t>(thorvald_flags::kControllerOk | latched_flags_);
  st.max_temperature_c = 35;
  st.battery_current_da = static_cast<int16_t>(-(p.current_da[0] + p.current_da[1]));
  st.battery_voltage_dv = 512;
  bus.send(encodeStatus(node_, st));
  if (mode_ == ThorvaldMode::kHomeSteering || !homing_reported_done_) {
    ThorvaldInfo info;
    info.type = 1;
    info.home_direction = mode_ == ThorvaldMode::kHomeSteering ? (steering_rad_ > 0 ? -1 : 1) : 0;
    info.home_speed_rpm = static_cast<int16_t>(ThorvaldScaling::steeringRpmFromSpeed(0.5 * d0.str_sim_v, d0));
    info.home_count = ThorvaldScaling::countFromSteering(home_travel_rad_, d0);
    bus.send(encodeInfo(node_, info));
    if (info.home_direction == 0) homing_reported_done_ = true;
  }
}

void ThorvaldDriveSim::sendInfo(CanBus& bus) {
  ThorvaldInfo info;
  info.type = static_cast<uint8_t>(info_kind_);
  info.controller_type = static_cast<uint8_t>(type_);
  info.script_version = 0x0203;
  info.encoder_ppr = type_ == 0 ? static_cast<int32_t>(channels_[0].str_enc_ppr) : 0;
  bus.send(encodeInfo(node_, info));
  info_kind_ = info_kind_ == 2 ? 3 : 2;
}

}  // namespace thorvald_can_devices
