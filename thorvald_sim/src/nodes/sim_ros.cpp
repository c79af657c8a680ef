#include "sim_ros.h"

#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <cmath>

#include "thorvald_sim/mjcf_compiler.h"
#include "thorvald_sim/world.h"

namespace thorvald_sim {

namespace {

template <typename T>
void param(const ros::NodeHandle& nh, const std::string& key, T& value) {
  nh.param(key, value, value);
}

double xmlNumber(XmlRpc::XmlRpcValue& v, const std::string& key, double def) {
  if (!v.hasMember(key)) return def;
  XmlRpc::XmlRpcValue& x = v[key];
  if (x.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(x);
  if (x.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(x);
  throw std::invalid_argument(key + ": expected a number");
}

}  // namespace

SimRos::SimRos(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh) {}

bool SimRos::loadParams() {
  auto& p = params_;
  param(pnh_, "world", p.world);
  param(pnh_, "truth_file", p.truth_file);
  param(pnh_, "world_frame", p.world_frame);
  param(pnh_, "real_time_factor", p.real_time_factor);
  param(pnh_, "control_period", p.control_period_s);
  param(pnh_, "ground_truth_rate", p.ground_truth_rate_hz);
  param(pnh_, "publish_map_tf", p.publish_map_tf);
  param(pnh_, "start_paused", p.start_paused);
  param(pnh_, "wait_for_description", p.wait_for_description_s);
  auto bad = [](const std::string& key, const std::string& expected) {
    ROS_FATAL("thorvald_sim: parameter ~%s: expected %s", key.c_str(), expected.c_str());
    return false;
  };
  if (p.world != "flat" && p.world != "greenhouse" && p.world != "cotton_row")
    return bad("world", "flat, greenhouse or cotton_row, got '" + p.world + "'");
  if (!(p.real_time_factor >= 0.0) || !std::isfinite(p.real_time_factor))
    return bad("real_time_factor", "0 (as fast as possible) or a positive number");
  if (!(p.control_period_s >= 0.001 && p.control_period_s <= 0.1)) return bad("control_period", "0.001 to 0.1 s");
  if (!(p.ground_truth_rate_hz > 0.0 && p.ground_truth_rate_hz <= 1000.0))
    return bad("ground_truth_rate", "a rate in (0, 1000] Hz");
  return true;
}

bool SimRos::buildWorld(WorldDescription* world) {
  try {
    if (params_.world == "flat") {
      double half = 100.0;
      param(pnh_, "flat/half_size", half);
      *world = makeFlatWorld(half);
    } else if (params_.world == "greenhouse") {
      GreenhouseParams g;
      ros::NodeHandle n(pnh_, "greenhouse");
      param(n, "rail_sets", g.rail_sets);
      param(n, "set_spacing", g.set_spacing_m);
      param(n, "rail_gauge", g.rail_gauge_m);
      param(n, "pipe_diameter", g.pipe_diameter_m);
      param(n, "rail_top", g.rail_top_m);
      param(n, "rail_length", g.rail_length_m);
      param(n, "rail_start_gap", g.rail_start_gap_m);
      param(n, "headland_depth", g.headland_depth_m);
      param(n, "row_ground_drop", g.row_ground_drop_m);
      param(n, "vent_every", g.vent_every);
      param(n, "vent_height", g.vent_height_m);
      GreenhouseTruth truth;
      *world = makeGreenhouseWorld(g, &truth);
      if (!params_.truth_file.empty() && !writeGreenhouseTruth(truth, params_.truth_file)) {
        ROS_FATAL("thorvald_sim: cannot write ~truth_file %s", params_.truth_file.c_str());
        return false;
      }
    } else {
      CottonRowParams c;
      ros::NodeHandle n(pnh_, "cotton_row");
      param(n, "plants", c.plants);
      param(n, "plant_spacing", c.plant_spacing_m);
      param(n, "first_plant_x", c.first_plant_x_m);
      param(n, "row_y", c.row_y_m);
      param(n, "plant_height", c.plant_height_m);
      param(n, "bolls_per_plant", c.bolls_per_plant);
      param(n, "slope_deg", c.slope_deg);
      int seed = 1;
      param(n, "seed", seed);
      c.seed = static_cast<unsigned>(seed);
      CottonRowTruth truth;
      *world = makeCottonRowWorld(c, &truth);
      if (!params_.truth_file.empty() && !writeCottonRowTruth(truth, params_.truth_file)) {
        ROS_FATAL("thorvald_sim: cannot write ~truth_file %s", params_.truth_file.c_str());
        return false;
      }
    }
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("thorvald_sim: world %s: parameter %s", params_.world.c_str(), e.what());
    return false;
  }
  return true;
}

bool SimRos::loadRobots(const WorldDescription& world) {
  // ~robots: list of {namespace, x, y, z, yaw, sensors}; default: one robot in the node's namespace.
  XmlRpc::XmlRpcValue list;
  if (!pnh_.getParam("robots", list)) {
    list.setSize(1);
    list[0]["namespace"] = std::string("");
    double x = 0, y = 0, yaw = 0;
    std::string sensors;
    param(pnh_, "x", x), param(pnh_, "y", y), param(pnh_, "yaw", yaw), param(pnh_, "sensors", sensors);
    list[0]["x"] = x, list[0]["y"] = y, list[0]["yaw"] = yaw, list[0]["sensors"] = sensors;
  }
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    ROS_FATAL("thorvald_sim: ~robots: expected a list of {namespace, x, y, yaw, sensors}");
    return false;
  }
  std::vector<RobotSpawn> spawns;
  std::vector<std::string> prefixes;
  std::vector<std::vector<SensorConfig>> sensors;
  std::vector<bool> physics;
  std::string default_encoders = "joint_simulator";
  param(pnh_, "encoders", default_encoders);
  for (int i = 0; i < list.size(); ++i) {
    const std::string where = "~robots[" + std::to_string(i) + "]";
    try {
      XmlRpc::XmlRpcValue& r = list[i];
      RobotSpawn s;
      s.name = r.hasMember("namespace") ? static_cast<std::string>(r["namespace"]) : std::string();
      s.x = xmlNumber(r, "x", 0), s.y = xmlNumber(r, "y", 0), s.z = xmlNumber(r, "z", 0.02);
      s.yaw = xmlNumber(r, "yaw", 0);
      ros::NodeHandle rn(nh_, s.name);
      std::string urdf;
      const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(params_.wait_for_description_s);
      while (!rn.getParam("robot_description", urdf) && ros::ok() && ros::WallTime::now() < deadline)
        ros::WallDuration(0.1).sleep();  // robot.launch may load it after we start
      if (urdf.empty()) {
        ROS_FATAL("thorvald_sim: %s: no %s after %.0f s", where.c_str(), rn.resolveName("robot_description").c_str(),
                  params_.wait_for_description_s);
        return false;
      }
      s.mjcf = urdfToMjcf(urdf, &s.root_link);
      const std::string prefix =
          s.root_link.size() > 10 ? s.root_link.substr(0, s.root_link.size() - 10) : std::string();
      const std::string sensor_file = r.hasMember("sensors") ? static_cast<std::string>(r["sensors"]) : "";
      sensors.push_back(sensor_file.empty() ? std::vector<SensorConfig>{} : loadSensorConfigFile(sensor_file));
      const std::string encoders = r.hasMember("encoders") ? static_cast<std::string>(r["encoders"]) : default_encoders;
      if (encoders != "joint_simulator" && encoders != "physics")
        throw std::invalid_argument("encoders: expected joint_simulator or physics, got '" + encoders + "'");
      physics.push_back(encoders == "physics");
      spawns.push_back(s);
      prefixes.push_back(prefix);
      ROS_INFO("thorvald_sim: robot '%s' (root %s) at %.2f %.2f yaw %.2f, %zu sensors", s.name.c_str(),
               s.root_link.c_str(), s.x, s.y, s.yaw, sensors.back().size());
    } catch (const std::exception& e) {
      ROS_FATAL("thorvald_sim: %s: %s", where.c_str(), e.what());
      return false;
    }
  }
  try {
    SceneOptions options;
    for (const auto& list : sensors)  // the offscreen buffer must hold the largest camera image
      for (const auto& c : list)
        if (c.type == SensorType::kDepthCamera) {
          options.camera_max_width = std::max(options.camera_max_width, c.depth.width);
          options.camera_max_height = std::max(options.camera_max_height, c.depth.height);
        }
    sim_ = std::make_unique<Simulation>(composeScene(world, spawns, options), spawns);
    for (size_t i = 0; i < spawns.size(); ++i)
      robots_.push_back(std::make_unique<RobotIo>(
          ros::NodeHandle(nh_, spawns[i].name), *sim_, i, prefixes[i], sensors[i], params_.world_frame,
          params_.publish_map_tf, [this]() -> CameraRenderer& { return renderer(); }, physics[i]));
  } catch (const std::exception& e) {
    ROS_FATAL("thorvald_sim: cannot build the scene: %s", e.what());
    return false;
  }
  return true;
}

bool SimRos::start() {
  if (!loadParams()) return false;
  WorldDescription world;
  if (!buildWorld(&world) || !loadRobots(world)) return false;
  steps_per_period_ = std::max(1, static_cast<int>(std::lround(params_.control_period_s / sim_->timestep())));
  paused_ = params_.start_paused;
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  pause_srv_ = pnh_.advertiseService("pause", &SimRos::onPause, this);
  unpause_srv_ = pnh_.advertiseService("unpause", &SimRos::onUnpause, this);
  reset_srv_ = pnh_.advertiseService("reset", &SimRos::onReset, this);
  step_srv_ = pnh_.advertiseService("step", &SimRos::onStep, this);
  updater_.setHardwareID("thorvald_sim");
  updater_.add("simulation", this, &SimRos::diagnose);
  rosgraph_msgs::Clock c;
  clock_pub_.publish(c);
  ROS_INFO("thorvald_sim: world %s, %zu robots, timestep %.4f s, real-time factor %g", params_.world.c_str(),
           robots_.size(), sim_->timestep(), params_.real_time_factor);
  return true;
}

CameraRenderer& SimRos::renderer() {
  if (!renderer_) {
    renderer_ = std::make_unique<CameraRenderer>(sim_->model());
    ROS_INFO("thorvald_sim: camera renderer ready (OSMesa, offscreen %dx%d)", renderer_->maxWidth(),
             renderer_->maxHeight());
  }
  return *renderer_;
}

void SimRos::advance() {
  sim_->step(steps_per_period_);
  rosgraph_msgs::Clock c;
  c.clock = ros::Time(sim_->time());
  clock_pub_.publish(c);
  for (auto& r : robots_) r->publish(c.clock, 1.0 / params_.ground_truth_rate_hz);
}

void SimRos::run() {
  ros::WallTime wall_start = ros::WallTime::now(), last_report = wall_start;
  double sim_start = sim_->time(), sim_at_report = sim_start;
  while (ros::ok()) {
    ros::spinOnce();
    if (paused_) {
      ros::WallDuration(0.005).sleep();
      wall_start = ros::WallTime::now();
      sim_start = sim_->time();
      continue;
    }
    advance();
    const ros::WallTime now = ros::WallTime::now();
    if ((now - last_report).toSec() >= 1.0) {
      achieved_rtf_ = (sim_->time() - sim_at_report) / (now - last_report).toSec();
      last_report = now;
      sim_at_report = sim_->time();
      updater_.force_update();
    }
    if (params_.real_time_factor > 0.0) {
      // Pace simulated time against the wall clock.
      const ros::WallTime due = wall_start + ros::WallDuration((sim_->time() - sim_start) / params_.real_time_factor);
      if (due > now) (due - now).sleep();
    }
  }
}

bool SimRos::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = true;
  return true;
}

bool SimRos::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = false;
  return true;
}

bool SimRos::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  // Simulated time keeps running forwards (nodes under /clock dislike time jumping back); the bodies go home.
  sim_->reset(true);
  ROS_INFO("thorvald_sim: reset every robot to its start pose at t = %.3f s", sim_->time());
  return true;
}

bool SimRos::onStep(Step::Request& req, Step::Response& res) {
  if (!paused_) {
    res.success = false;
    res.message = "not paused: call ~pause first";
  } else {
    for (uint32_t i = 0; i < req.steps; ++i) sim_->step(1);
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(sim_->time());
    clock_pub_.publish(c);
    for (auto& r : robots_) r->publish(c.clock, 1.0 / params_.ground_truth_rate_hz);
    res.success = true;
  }
  res.time = sim_->time();
  return true;
}

void SimRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  if (sim_->divergences() > 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "physics diverged and was reset");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, paused_ ? "paused" : "running");
  stat.add("world", params_.world);
  stat.add("simulated time [s]", sim_->time());
  stat.add("real-time factor achieved", achieved_rtf_);
  stat.add("real-time factor requested", params_.real_time_factor);
  stat.add("divergences", sim_->divergences());
  stat.add("camera frames rendered", renderer_ ? renderer_->frames() : 0ul);
  for (const auto& r : robots_) r->diagnostics(stat);
}

}  // namespace thorvald_sim
