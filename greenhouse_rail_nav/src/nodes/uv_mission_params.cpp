#include "uv_mission_params.h"

namespace greenhouse_rail_nav {

namespace {

/// The run to a row's end of known length and the lamps (config/uv_lamps.yaml): the treatment speed must give at
/// least the set dose.
void readRowEndParams(thorvald_common::ParamReader& params, RailRunParams* r) {
  using R = thorvald_common::ParamRange;
  r->rail_end_margin_m = params.number("rail_end_margin", r->rail_end_margin_m, R::closed(0.0, 5.0), "m");
  r->wall_guard_range_m = params.number("wall_guard_range", r->wall_guard_range_m, R::aboveUpTo(0.0, 10.0), "m");
  r->lamp_length_m = params.number("lamp_length", r->lamp_length_m, R::aboveUpTo(0.0, 5.0), "m");
  r->lamp_offset_m = params.number("lamp_offset", r->lamp_offset_m, R::closed(-5.0, 5.0), "m");
  const double power = params.number("lamp_power", 60.0, R::aboveUpTo(0.0, 10000.0), "W");
  const double dose = params.number("target_dose", 100.0, R::aboveUpTo(0.0, 1e6), "J/m");
  if (power / r->treat_speed_mps < dose - 1e-9)
    throw thorvald_common::ParamError("uv_mission: treat_speed " + std::to_string(r->treat_speed_mps) +
                                      " m/s gives less than the set dose target_dose (lamp_power / treat_speed)");
}

/// Reads the robot interface's and the mission's motion parameters (in this order; defaults from their structs).
void readMotionParams(thorvald_common::ParamReader& params, NodeSettings* s) {
  using R = thorvald_common::ParamRange;
  MissionIoConfig& io = s->io;
  UvMissionParams& p = s->mission;
  io.map_frame = params.text("map_frame", io.map_frame);
  io.base_frame = params.text("base_frame", io.base_frame);
  io.rate_hz = params.number("control_rate", io.rate_hz, R::aboveUpTo(1.0, 200.0), "Hz");
  io.odom_timeout_s = params.number("odom_timeout", io.odom_timeout_s, R::above(0.0), "s");
  io.pause_rail_detection = params.flag("pause_rail_detection", io.pause_rail_detection);
  p.alignment.approach_x_m = params.number("approach_x", p.alignment.approach_x_m, R::closed(-5.0, -0.2), "m");
  p.alignment.y_limit_m = params.number("y_limit", p.alignment.y_limit_m, R::aboveUpTo(0.0, 0.1), "m");
  p.alignment.yaw_limit_rad = params.number("yaw_limit", p.alignment.yaw_limit_rad, R::aboveUpTo(0.0, 0.2), "rad");
  p.alignment.max_turn_rad = params.number("max_turn", p.alignment.max_turn_rad, R::closed(0.1, 1.4), "rad");
  p.alignment.run_up_m = params.number("run_up", p.alignment.run_up_m, R::aboveUpTo(0.0, 5.0), "m");
  p.motion.max_speed_mps = params.number("align_speed", p.motion.max_speed_mps, R::aboveUpTo(0.0, 1.0), "m/s");
  p.motion.max_turn_rate_rps = params.number("turn_rate", p.motion.max_turn_rate_rps, R::aboveUpTo(0.0, 2.0), "rad/s");
  p.motion.response_time_s = params.number("response_time", p.motion.response_time_s, R::closed(0.0, 1.0), "s");
  p.rail_run.treat_speed_mps = params.number("treat_speed", p.rail_run.treat_speed_mps, R::aboveUpTo(0.0, 1.5), "m/s");
  p.rail_run.return_speed_mps =
      params.number("return_speed", p.rail_run.return_speed_mps, R::aboveUpTo(0.0, 1.5), "m/s");
  p.rail_run.end_wall_range_m = params.number("end_wall_range", p.rail_run.end_wall_range_m, R::above(0.0), "m");
  p.rail_run.slow_fraction = params.number("slow_fraction", p.rail_run.slow_fraction, R::closed(0.1, 0.99));
  p.rail_run.return_overrun_m = params.number("return_overrun", p.rail_run.return_overrun_m, R::closed(0.0, 10.0), "m");
  p.rail_run.return_overrun_fraction =
      params.number("return_overrun_fraction", p.rail_run.return_overrun_fraction, R::closed(0.0, 1.0));
  p.rail_run.return_stall_s =
      params.number("return_stall_time", p.rail_run.return_stall_s, R::aboveUpTo(0.0, 60.0), "s");
  p.rail_run.return_max_heading_error_rad = params.number(
      "return_max_heading_error", p.rail_run.return_max_heading_error_rad, R::aboveUpTo(0.0, 3.14), "rad");
  readRowEndParams(params, &p.rail_run);
}

/// Reads the mission's steps' parameters (in this order; defaults from UvMissionParams).
void readStepParams(thorvald_common::ParamReader& params, UvMissionParams* p) {
  using R = thorvald_common::ParamRange;
  p->nav_timeout_s = params.number("nav_timeout", p->nav_timeout_s, R::above(0.0), "s");
  p->detect_timeout_s = params.number("detect_timeout", p->detect_timeout_s, R::above(0.0), "s");
  p->search_step_rad = params.number("search_step", p->search_step_rad, R::aboveUpTo(0.0, 1.0), "rad");
  p->search_limit_rad = params.number("search_limit", p->search_limit_rad, R::aboveUpTo(0.0, 3.14), "rad");
  p->max_align_attempts = params.integer("max_align_attempts", p->max_align_attempts, 1, 50);
  p->enter_speed_mps = params.number("enter_speed", p->enter_speed_mps, R::aboveUpTo(0.0, 0.3), "m/s");
  p->enter_max_distance_m = params.number("enter_max_distance", p->enter_max_distance_m, R::above(0.0), "m");
  p->on_rails_margin_m = params.number("on_rails_margin", p->on_rails_margin_m, R::closed(0.0, 1.0), "m");
  p->enter_line_frequency_rps =
      params.number("enter_line_frequency", p->enter_line_frequency_rps, R::closed(0.0, 3.0), "rad/s");
  p->secure_wait_s = params.number("secure_wait", p->secure_wait_s, R::aboveUpTo(0.0, 10.0), "s");
  p->recover_reverse_max_m = params.number("recover_reverse_max", p->recover_reverse_max_m, R::closed(0.0, 5.0), "m");
  p->min_lit_fraction = params.number("min_lit_fraction", p->min_lit_fraction, R::aboveUpTo(0.0, 1.0));
  p->relight_overlap_m = params.number("relight_overlap", p->relight_overlap_m, R::closed(0.0, 1.0), "m");
  p->relight_run_up_m = params.number("relight_run_up", p->relight_run_up_m, R::closed(0.0, 2.0), "m");
}

}  // namespace

/// Every private parameter, checked; throws ParamError naming the bad one.
NodeSettings readSettings(ros::NodeHandle& pnh) {
  thorvald_common::ParamReader params(pnh);
  NodeSettings s;
  s.rail_sets_file = params.text("rail_sets_file", "");
  s.progress_file = params.text("progress_file", "");
  s.autostart = params.flag("autostart", true);
  s.exit_when_done = params.flag("exit_when_done", false);
  s.wait_for_rail_sets_s =
      params.number("wait_for_rail_sets", 0.0, thorvald_common::ParamRange::closed(0.0, 3600.0), "s");
  readMotionParams(params, &s);
  s.io.zones.map_frame = s.io.map_frame;
  s.io.zones.base_frame = s.io.base_frame;
  readStepParams(params, &s.mission);
  s.rail_length_m = params.number("rail_length", 0.0, thorvald_common::ParamRange::closed(0.0, 1000.0), "m");
  ZoneWatch::readParams(params, &s.io.zones);
  s.mission.zone = s.io.zones.zone;
  params.finish();
  const std::string problems = s.mission.validate();
  if (!problems.empty()) throw thorvald_common::ParamError("uv_mission: " + problems);
  if (s.rail_sets_file.empty())
    throw thorvald_common::ParamError("uv_mission: ~rail_sets_file is required (map_analyzer's output)");
  return s;
}

}  // namespace greenhouse_rail_nav
