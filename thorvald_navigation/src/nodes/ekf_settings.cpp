#include "ekf_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace thorvald_navigation {

namespace {

using thorvald_common::ParamError;
using R = thorvald_common::ParamRange;

// robot_localization ekf keys this node accepts but does not implement.
const char* const kUnsupportedGlobal[] = {"use_control",
                                          "stamped_control",
                                          "control_timeout",
                                          "control_config",
                                          "acceleration_limits",
                                          "acceleration_gains",
                                          "deceleration_limits",
                                          "deceleration_gains",
                                          "smooth_lagged_data",
                                          "history_length",
                                          "dynamic_process_noise_covariance",
                                          "reset_on_time_jump",
                                          "predict_to_current_time",
                                          "disabled_at_startup",
                                          "debug",
                                          "debug_out_file",
                                          "transform_time_offset",
                                          "transform_timeout",
                                          "publish_acceleration",
                                          "permit_corrected_publication",
                                          "base_link_frame_output"};
// Per-input keys accepted without effect (this node fuses each message when it arrives).
const char* const kUnsupportedPerInput[] = {"_nodelay", "_pose_use_child_frame"};

/// A list of numbers where an entry may also be a string holding a number: rosparam (YAML 1.1) loads `1e-9`, as
/// robot_localization's own template writes it, as a string, and robot_localization reads it as a number.
std::vector<double> lenientNumbers(thorvald_common::ParamReader& r, const std::string& name, std::size_t max_size) {
  XmlRpc::XmlRpcValue v;
  if (!r.raw(name, &v)) return {};
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || static_cast<std::size_t>(v.size()) > max_size)
    throw ParamError(r.node() + ": ~" + name + ": found " + thorvald_common::describeParamValue(v) +
                     ", expected a list of at most " + std::to_string(max_size) + " numbers");
  std::vector<double> out;
  for (int i = 0; i < v.size(); ++i) {
    XmlRpc::XmlRpcValue& e = v[i];
    double d = std::nan("");
    if (e.getType() == XmlRpc::XmlRpcValue::TypeDouble) d = static_cast<double>(e);
    if (e.getType() == XmlRpc::XmlRpcValue::TypeInt) d = static_cast<int>(e);
    if (e.getType() == XmlRpc::XmlRpcValue::TypeString) {
      const std::string text = static_cast<std::string>(e);
      char* end = nullptr;
      d = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0') d = std::nan("");
    }
    if (!std::isfinite(d))
      throw ParamError(r.node() + ": ~" + name + "[" + std::to_string(i) + "]: found " +
                       thorvald_common::describeParamValue(e) + ", expected a number");
    out.push_back(d);
  }
  return out;
}

std::vector<double> matrix(thorvald_common::ParamReader& r, const std::string& name) {
  const std::vector<double> m = lenientNumbers(r, name, 225);
  if (!m.empty() && m.size() != 225 && m.size() != 15)
    throw ParamError(r.node() + ": ~" + name +
                     ": expected a 15x15 matrix (225 numbers) or its 15-entry diagonal, got " +
                     std::to_string(m.size()) + " numbers");
  return m;
}

void readMatrix(thorvald_common::ParamReader& r, const std::string& name, Cov15* out) {
  const std::vector<double> m = matrix(r, name);
  if (m.empty()) return;
  Cov15 c = Cov15::Zero();
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j)
      c(i, j) =
          m.size() == 225 ? m[static_cast<std::size_t>(i * 15 + j)] : (i == j ? m[static_cast<std::size_t>(i)] : 0.0);
  for (int i = 0; i < 15; ++i)
    if (!(c(i, i) >= 0.0))
      throw ParamError(r.node() + ": ~" + name + ": diagonal entry for " + kFusionStateNames[i] + " must be >= 0");
  *out = 0.5 * (c + c.transpose());
}

// Entries a kind of message can carry; robot_localization ignores the others.
bool carries(EkfInput::Kind kind, int i) {
  switch (kind) {
    case EkfInput::kOdom:
      return i < 12;
    case EkfInput::kImu:
      return (i >= 3 && i < 6) || i >= 9;
    case EkfInput::kPose:
      return i < 6;
    case EkfInput::kTwist:
      return i >= 6 && i < 12;
  }
  return false;
}

EkfInput readInput(thorvald_common::ParamReader& r, EkfInput::Kind kind, const std::string& name, EkfSettings* s) {
  EkfInput in;
  in.kind = kind;
  in.name = name;
  in.topic = r.text(name, "");
  if (in.topic.empty()) throw ParamError(r.node() + ": ~" + name + ": the topic must not be empty");
  const std::vector<bool> cfg = r.flags(name + "_config", std::vector<bool>(15, false), 15, 15);
  for (int i = 0; i < 15; ++i) {
    in.config.use[i] = cfg[i] && carries(kind, i);
    if (cfg[i] && !carries(kind, i))
      s->unsupported_set.push_back(name + "_config: " + kFusionStateNames[i] + " (this message does not carry it)");
  }
  in.config.differential = r.flag(name + "_differential", false);
  in.config.relative = r.flag(name + "_relative", false);
  in.queue_size = r.integer(name + "_queue_size", 1, 1, 10000);
  if (kind == EkfInput::kOdom) {
    in.config.pose_gate = readRejectionThreshold(r, name + "_pose_rejection_threshold");
    in.config.twist_gate = readRejectionThreshold(r, name + "_twist_rejection_threshold");
  } else if (kind == EkfInput::kImu) {
    in.config.pose_gate = readRejectionThreshold(r, name + "_pose_rejection_threshold");
    in.config.angular_velocity_gate = readImuRateRejectionThreshold(r, name);
    in.config.linear_acceleration_gate = readRejectionThreshold(r, name + "_linear_acceleration_rejection_threshold");
    in.config.remove_gravity = r.flag(name + "_remove_gravitational_acceleration", false);
  } else if (kind == EkfInput::kPose) {
    in.config.pose_gate = readRejectionThreshold(r, name + "_rejection_threshold");
  } else {
    in.config.twist_gate = readRejectionThreshold(r, name + "_rejection_threshold");
  }
  for (const char* suffix : kUnsupportedPerInput)
    if (r.has(name + suffix)) s->unsupported_set.push_back(name + suffix);
  return in;
}

}  // namespace

bool EkfInput::position_source() const {
  return (config.use[kFx] || config.use[kFy]) && !config.differential && kind != kImu;
}

EkfSettings readEkfSettings(thorvald_common::ParamReader& r) {
  EkfSettings s;
  s.frequency = r.number("frequency", s.frequency, R::aboveUpTo(0.0, 1000.0), "Hz");
  s.sensor_timeout = r.number("sensor_timeout", 1.0 / s.frequency, R::above(0.0), "s");
  s.two_d_mode = r.flag("two_d_mode", s.two_d_mode);
  s.publish_tf = r.flag("publish_tf", s.publish_tf);
  r.flag("print_diagnostics", true);  // diagnostics are always published
  s.map_frame = r.text("map_frame", s.map_frame);
  s.odom_frame = r.text("odom_frame", s.odom_frame);
  s.base_link_frame = r.text("base_link_frame", s.base_link_frame);
  s.world_frame = r.text("world_frame", s.odom_frame);
  if (s.world_frame != s.odom_frame && s.world_frame != s.map_frame)
    throw ParamError(r.node() + ": ~world_frame: '" + s.world_frame + "' must be ~odom_frame ('" + s.odom_frame +
                     "') or ~map_frame ('" + s.map_frame + "')");
  readMatrix(r, "process_noise_covariance", &s.process_noise);
  readMatrix(r, "initial_estimate_covariance", &s.initial_covariance);
  const std::vector<double> x0 = lenientNumbers(r, "initial_state", 15);
  if (!x0.empty() && x0.size() != 15) throw ParamError(r.node() + ": ~initial_state: expected 15 numbers");
  for (std::size_t i = 0; i < x0.size(); ++i) s.initial_state(static_cast<int>(i)) = x0[i];
  const double g = r.number("gravitational_acceleration", 9.80665, R::above(0.0), "m/s^2");
  s.gps_timeout = r.number("gps_timeout", s.gps_timeout, R::above(0.0), "s");
  s.input_timeout = r.number("input_timeout", s.input_timeout, R::above(0.0), "s");
  for (const char* key : kUnsupportedGlobal)
    if (r.has(key)) s.unsupported_set.push_back(key);
  const std::pair<const char*, EkfInput::Kind> kinds[] = {
      {"odom", EkfInput::kOdom}, {"imu", EkfInput::kImu}, {"pose", EkfInput::kPose}, {"twist", EkfInput::kTwist}};
  for (const auto& [prefix, kind] : kinds) {
    for (int n = 0; n < 10; ++n) {  // robot_localization counts from 0; gaps are allowed here
      const std::string name = prefix + std::to_string(n);
      if (!r.has(name)) continue;
      EkfInput in = readInput(r, kind, name, &s);
      in.config.gravity = g;
      in.status_timeout_s = in.position_source() ? s.gps_timeout : s.input_timeout;
      s.inputs.push_back(in);
    }
  }
  if (s.inputs.empty()) throw ParamError(r.node() + ": no input: set at least one of ~odom0, ~imu0, ~pose0, ~twist0");
  return s;
}

std::string unsupportedWarning(const EkfSettings& s) {
  if (s.unsupported_set.empty()) return {};
  std::string w = "robot_localization features not implemented here, ignored:";
  for (const std::string& k : s.unsupported_set) w += " " + k + ",";
  w.pop_back();
  return w + " (see the README's ekf_localization limits)";
}

double readRejectionThreshold(thorvald_common::ParamReader& r, const std::string& name) {
  return r.number(name, std::numeric_limits<double>::infinity(), thorvald_common::ParamRange::above(0.0), "sigma");
}

double readImuRateRejectionThreshold(thorvald_common::ParamReader& r, const std::string& imu) {
  return std::min(readRejectionThreshold(r, imu + "_angular_velocity_rejection_threshold"),
                  readRejectionThreshold(r, imu + "_twist_rejection_threshold"));
}

}  // namespace thorvald_navigation
