#include "world_params.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace thorvald_sim {

namespace {

using thorvald_common::ParamRange;

double number(XmlRpc::XmlRpcValue& v, const std::string& where) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
  throw std::invalid_argument(where + ": found " + thorvald_common::describeParamValue(v) + ", expected a number");
}

/// A list of `n` numbers (n = 0: any length).
std::vector<double> numbers(XmlRpc::XmlRpcValue& v, const std::string& where, int n) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || (n > 0 && v.size() != n))
    throw std::invalid_argument(where + ": expected a list of " + (n > 0 ? std::to_string(n) + " " : "") +
                                "numbers, found " + thorvald_common::describeParamValue(v));
  std::vector<double> out;
  for (int i = 0; i < v.size(); ++i) out.push_back(number(v[i], where + "[" + std::to_string(i) + "]"));
  return out;
}

void readVariation(thorvald_common::ParamReader& params, GreenhouseVariation* v) {
  const std::string k = "greenhouse/variation/";
  *v = greenhouseVariationProfile(params.choice("world_variation", "none", {"none", "pipes", "harsh"}));
  v->seed = static_cast<unsigned>(params.integer(k + "seed", static_cast<int>(v->seed), 0));
  v->pipe_end_offset_m = params.number(k + "pipe_end_offset", v->pipe_end_offset_m, ParamRange::closed(0.0, 0.1), "m");
  v->pipe_bend_length_m =
      params.number(k + "pipe_bend_length", v->pipe_bend_length_m, ParamRange::closed(0.05, 5.0), "m");
  v->pipe_gap_probability =
      params.number(k + "pipe_gap_probability", v->pipe_gap_probability, ParamRange::closed(0.0, 1.0));
  v->pipe_gap_m = params.number(k + "pipe_gap", v->pipe_gap_m, ParamRange::closed(0.0, 0.5), "m");
  v->rust_probability = params.number(k + "rust_probability", v->rust_probability, ParamRange::closed(0.0, 1.0));
  v->headland_slope_deg =
      params.number(k + "headland_slope_deg", v->headland_slope_deg, ParamRange::closed(0.0, 10.0), "deg");
  v->headland_bumps = params.integer(k + "headland_bumps", v->headland_bumps, 0, 1000);
  v->bump_slope_deg = params.number(k + "bump_slope_deg", v->bump_slope_deg, ParamRange::closed(0.05, 10.0), "deg");
  v->hoses = params.integer(k + "hoses", v->hoses, 0, 100);
  v->crates = params.integer(k + "crates", v->crates, 0, 100);
  v->trolleys = params.integer(k + "trolleys", v->trolleys, 0, 100);
  v->trolley_x_m = params.number(k + "trolley_x", v->trolley_x_m, ParamRange::closed(-100.0, -0.3), "m");
  v->rail_length_jitter_m =
      params.number(k + "rail_length_jitter", v->rail_length_jitter_m, ParamRange::closed(0.0, 100.0), "m");
  v->set_spacing_jitter_m =
      params.number(k + "set_spacing_jitter", v->set_spacing_jitter_m, ParamRange::closed(0.0, 1.0), "m");
}

/// Moves a spec's path and region from rail set `k`'s frame into the world.
void intoRailSet(ActorSpec* s, const GreenhouseTruth& truth, int k, const std::string& where) {
  if (k < 0 || k >= static_cast<int>(truth.rail_sets.size()))
    throw std::invalid_argument(where + "rail_set: " + std::to_string(k) + " is not a rail set (0 .. " +
                                std::to_string(truth.rail_sets.size() - 1) + ")");
  const RailSetTruth& r = truth.rail_sets[k];
  for (auto& w : s->path) w.x += r.start_x, w.y += r.start_y;
  s->trigger_x += r.start_x, s->trigger_y += r.start_y;
  s->region[0] += r.start_x, s->region[1] += r.start_x, s->region[2] += r.start_y, s->region[3] += r.start_y;
}

ActorSpec parseActor(XmlRpc::XmlRpcValue& a, const GreenhouseTruth* truth, const std::string& where) {
  static const std::vector<std::string> known = {"name",     "kind",   "path",   "loop",   "random_walk",
                                                 "rail_set", "radius", "height", "length", "trigger"};
  if (a.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    throw std::invalid_argument(where + "expected a map {name, kind, path, ...}");
  for (const auto& m : a)
    if (std::find(known.begin(), known.end(), m.first) == known.end())
      throw std::invalid_argument(where + "unknown key '" + m.first + "'");
  ActorSpec s;
  if (!a.hasMember("name") || a["name"].getType() != XmlRpc::XmlRpcValue::TypeString)
    throw std::invalid_argument(where + "name: expected a string");
  s.name = static_cast<std::string>(a["name"]);
  const std::string kind = a.hasMember("kind") ? static_cast<std::string>(a["kind"]) : "person";
  if (kind != "person" && kind != "trolley")
    throw std::invalid_argument(where + "kind: expected person or trolley, got '" + kind + "'");
  s.kind = kind == "person" ? ActorKind::kPerson : ActorKind::kTrolley;
  if (s.kind == ActorKind::kTrolley) s.radius_m = 0.3, s.height_m = 1.0, s.length_m = 1.0;
  if (a.hasMember("path"))
    for (int i = 0; i < a["path"].size(); ++i) {
      const auto p = numbers(a["path"][i], where + "path[" + std::to_string(i) + "]", 3);
      s.path.push_back({p[0], p[1], p[2]});
    }
  if (a.hasMember("loop")) s.loop = static_cast<bool>(a["loop"]);
  if (a.hasMember("random_walk")) {
    XmlRpc::XmlRpcValue& w = a["random_walk"];
    s.random_walk = true;
    const auto r = numbers(w["region"], where + "random_walk/region", 4);
    std::copy(r.begin(), r.end(), s.region);
    if (w.hasMember("speed")) s.speed_mps = number(w["speed"], where + "random_walk/speed");
    if (w.hasMember("pause")) s.pause_s = number(w["pause"], where + "random_walk/pause");
    if (w.hasMember("seed")) s.seed = static_cast<unsigned>(number(w["seed"], where + "random_walk/seed"));
  }
  if (a.hasMember("trigger")) {  // {x, y, radius}: starts the script when a robot's body comes that near the point
    XmlRpc::XmlRpcValue& g = a["trigger"];
    if (g.getType() != XmlRpc::XmlRpcValue::TypeStruct || !g.hasMember("x") || !g.hasMember("y") ||
        !g.hasMember("radius"))
      throw std::invalid_argument(where + "trigger: expected {x, y, radius}");
    s.trigger_x = number(g["x"], where + "trigger/x");
    s.trigger_y = number(g["y"], where + "trigger/y");
    s.trigger_radius_m = number(g["radius"], where + "trigger/radius");
    if (!(s.trigger_radius_m > 0.0)) throw std::invalid_argument(where + "trigger/radius: must be > 0 m");
  }
  if (a.hasMember("radius")) s.radius_m = number(a["radius"], where + "radius");
  if (a.hasMember("height")) s.height_m = number(a["height"], where + "height");
  if (a.hasMember("length")) s.length_m = number(a["length"], where + "length");
  if (a.hasMember("rail_set")) {
    if (!truth) throw std::invalid_argument(where + "rail_set: only in the greenhouse world");
    intoRailSet(&s, *truth, static_cast<int>(number(a["rail_set"], where + "rail_set")), where);
  }
  return s;
}

}  // namespace

void readGreenhouseParams(thorvald_common::ParamReader& params, GreenhouseParams* g) {
  g->rail_sets = params.integer("greenhouse/rail_sets", g->rail_sets, 1, 200);
  g->set_spacing_m = params.number("greenhouse/set_spacing", g->set_spacing_m, ParamRange::aboveUpTo(0.2, 10.0), "m");
  g->rail_gauge_m = params.number("greenhouse/rail_gauge", g->rail_gauge_m, ParamRange::aboveUpTo(0.1, 2.0), "m");
  g->pipe_diameter_m =
      params.number("greenhouse/pipe_diameter", g->pipe_diameter_m, ParamRange::aboveUpTo(0.005, 0.3), "m");
  g->rail_top_m = params.number("greenhouse/rail_top", g->rail_top_m, ParamRange::aboveUpTo(0.0, 1.0), "m");
  g->rail_length_m = params.number("greenhouse/rail_length", g->rail_length_m, ParamRange::aboveUpTo(0.5, 500.0), "m");
  g->rail_start_gap_m =
      params.number("greenhouse/rail_start_gap", g->rail_start_gap_m, ParamRange::closed(0.0, 2.0), "m");
  g->headland_depth_m =
      params.number("greenhouse/headland_depth", g->headland_depth_m, ParamRange::aboveUpTo(1.0, 100.0), "m");
  g->row_ground_drop_m =
      params.number("greenhouse/row_ground_drop", g->row_ground_drop_m, ParamRange::closed(0.0, 2.0), "m");
  g->vent_every = params.integer("greenhouse/vent_every", g->vent_every, 0, 1000);
  g->vent_height_m = params.number("greenhouse/vent_height", g->vent_height_m, ParamRange::aboveUpTo(0.0, 5.0), "m");
  g->vent_diameter_m =
      params.number("greenhouse/vent_diameter", g->vent_diameter_m, ParamRange::aboveUpTo(0.01, 2.0), "m");
  g->wall_margin_m = params.number("greenhouse/wall_margin", g->wall_margin_m, ParamRange::aboveUpTo(0.2, 20.0), "m");
  g->plant_bottom_m =
      params.number("greenhouse/plant_bottom", g->plant_bottom_m, ParamRange::aboveUpTo(0.0, 10.0), "m");
  g->plant_row_start_m =
      params.number("greenhouse/plant_row_start", g->plant_row_start_m, ParamRange::closed(0.0, 100.0), "m");
  g->plant_row_end_gap_m =
      params.number("greenhouse/plant_row_end_gap", g->plant_row_end_gap_m, ParamRange::closed(0.0, 100.0), "m");
  readVariation(params, &g->variation);
}

std::vector<ActorSpec> parseActors(XmlRpc::XmlRpcValue& list, const GreenhouseTruth* truth) {
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray)
    throw std::invalid_argument("~actors: expected a list of {name, kind, path, ...}");
  std::vector<ActorSpec> specs;
  for (int i = 0; i < list.size(); ++i)
    specs.push_back(parseActor(list[i], truth, "~actors[" + std::to_string(i) + "]: "));
  return specs;
}

}  // namespace thorvald_sim
