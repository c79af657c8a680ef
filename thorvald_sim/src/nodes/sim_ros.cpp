#include "sim_ros.h"

#include <XmlRpcException.h>
#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <cmath>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_sim/mjcf_compiler.h"
#include "thorvald_sim/world.h"
#include "world_params.h"

namespace thorvald_sim {

namespace {
/// [s] of wall clock a paced simulation may make up by running faster than requested; beyond it the lag is dropped.
constexpr double kMaxCatchUpS = 0.05;

/// The scene's options: wheel shape, and an offscreen buffer that holds the largest camera image and no more
/// (llvmpipe's cost per frame grows with the buffer, not only with the image drawn into it).
SceneOptions sceneOptions(bool sphere_wheels, const std::vector<std::vector<SensorConfig>>& sensors) {
  SceneOptions options;
  options.sphere_wheels = sphere_wheels;
  int camera_width = 0, camera_height = 0;
  for (const auto& list : sensors)
    for (const auto& c : list)
      if (c.type == SensorType::kDepthCamera) {
        camera_width = std::max(camera_width, c.depth.width);
        camera_height = std::max(camera_height, c.depth.height);
      }
  if (camera_width > 0) options.camera_max_width = camera_width, options.camera_max_height = camera_height;
  return options;
}

/// The surface `choice` names, or for `auto` the world's surface in the datasheet profile when any robot's sensor
/// file asks for it (else dry concrete, the ideal ground).
Ground groundUnderWheels(const std::string& choice, const std::string& world_name,
                         const std::vector<std::vector<SensorConfig>>& sensors) {
  if (choice != "auto") return *groundFromName(choice);
  bool datasheet = false;
  for (const auto& list : sensors)
    for (const auto& c : list) datasheet = datasheet || c.realism == Realism::kDatasheet;
  return groundOfWorld(world_name, datasheet ? Realism::kDatasheet : Realism::kIdeal);
}

double xmlNumber(XmlRpc::XmlRpcValue& v, const std::string& key, double def) {
  if (!v.hasMember(key)) return def;
  XmlRpc::XmlRpcValue& x = v[key];
  double out = 0.0;
  if (x.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    out = static_cast<double>(x);
  else if (x.getType() == XmlRpc::XmlRpcValue::TypeInt)
    out = static_cast<int>(x);
  else
    throw std::invalid_argument(key + ": found " + thorvald_common::describeParamValue(x) + ", expected a number");
  if (!std::isfinite(out)) throw std::invalid_argument(key + ": expected a finite number");
  return out;
}

std::string xmlText(XmlRpc::XmlRpcValue& v, const std::string& key, const std::string& def) {
  if (!v.hasMember(key)) return def;
  XmlRpc::XmlRpcValue& x = v[key];
  if (x.getType() != XmlRpc::XmlRpcValue::TypeString)
    throw std::invalid_argument(key + ": found " + thorvald_common::describeParamValue(x) + ", expected a string");
  return static_cast<std::string>(x);
}

}  // namespace

SimRos::SimRos(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh) {}

bool SimRos::loadParams() {
  using thorvald_common::ParamRange;
  try {
    thorvald_common::ParamReader params(pnh_, "thorvald_sim");
    auto& p = params_;
    p.world = params.choice("world", p.world, {"flat", "greenhouse", "cotton_row"});
    p.truth_file = params.text("truth_file", p.truth_file);
    p.world_frame = params.text("world_frame", p.world_frame);
    p.real_time_factor = params.number("real_time_factor", p.real_time_factor, ParamRange::closed(0.0, 1000.0));
    p.control_period_s = params.number("control_period", p.control_period_s, ParamRange::closed(0.001, 0.1), "s");
    p.ground_truth_rate_hz =
        params.number("ground_truth_rate", p.ground_truth_rate_hz, ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
    p.publish_map_tf = params.flag("publish_map_tf", p.publish_map_tf);
    p.sphere_wheels = params.flag("sphere_wheels", p.sphere_wheels);
    p.ground = params.choice("ground", p.ground, {"dry_concrete", "wet_concrete", "loose_soil", "auto"});
    p.start_paused = params.flag("start_paused", p.start_paused);
    p.wait_for_description_s =
        params.number("wait_for_description", p.wait_for_description_s, ParamRange::closed(0.0, 3600.0), "s");
    p.encoders = params.choice("encoders", p.encoders, {"joint_simulator", "physics"});
    if (params.raw("robots", &p.robots)) {
      for (const char* single : {"x", "y", "yaw", "sensors"})
        params.reject(single, "~robots is set: give the pose and sensors in its entries");
    } else {
      p.robots.setSize(1);
      p.robots[0]["namespace"] = std::string("");
      p.robots[0]["x"] = params.number("x", 0.0, ParamRange::any(), "m");
      p.robots[0]["y"] = params.number("y", 0.0, ParamRange::any(), "m");
      p.robots[0]["yaw"] = params.number("yaw", 0.0, ParamRange::any(), "rad");
      p.robots[0]["sensors"] = params.text("sensors", "");
    }
    // The world's own sub-tree: only the selected world's keys are read, the others are reported unread.
    if (p.world == "flat") {
      p.flat_half_size_m =
          params.number("flat/half_size", p.flat_half_size_m, ParamRange::aboveUpTo(0.5, 10000.0), "m");
    } else if (p.world == "greenhouse") {
      readGreenhouseParams(params, &p.greenhouse);
    } else {
      auto& c = p.cotton_row;
      c.plants = params.integer("cotton_row/plants", c.plants, 0, 10000);
      c.plant_spacing_m =
          params.number("cotton_row/plant_spacing", c.plant_spacing_m, ParamRange::aboveUpTo(0.01, 10.0), "m");
      c.first_plant_x_m = params.number("cotton_row/first_plant_x", c.first_plant_x_m, ParamRange::any(), "m");
      c.row_y_m = params.number("cotton_row/row_y", c.row_y_m, ParamRange::any(), "m");
      c.plant_height_m =
          params.number("cotton_row/plant_height", c.plant_height_m, ParamRange::aboveUpTo(0.05, 5.0), "m");
      c.bolls_per_plant = params.integer("cotton_row/bolls_per_plant", c.bolls_per_plant, 0, 1000);
      c.slope_deg = params.number("cotton_row/slope_deg", c.slope_deg, ParamRange::closed(-45.0, 45.0), "deg");
      c.seed = static_cast<unsigned>(params.integer("cotton_row/seed", static_cast<int>(c.seed), 0));
      c.leaves_per_plant = params.integer("cotton_row/leaves_per_plant", c.leaves_per_plant, 0, 1000);
      c.leaf_over_boll_fraction =
          params.number("cotton_row/leaf_over_boll_fraction", c.leaf_over_boll_fraction, ParamRange::closed(0.0, 1.0));
    }
    params.raw("actors", &p.actors);
    p.actors_give_way_s = params.number("actors_give_way", p.actors_give_way_s, ParamRange::closed(0.0, 3600.0), "s");
    params.alsoRead("diagnostic_period");
    params.finish();
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL_STREAM(e.what());
    return false;
  }
  return true;
}

bool SimRos::buildWorld(WorldDescription* world) {
  try {
    if (params_.world == "flat") {
      *world = makeFlatWorld(params_.flat_half_size_m);
    } else if (params_.world == "greenhouse") {
      auto truth = std::make_shared<GreenhouseTruth>();
      *world = makeGreenhouseWorld(params_.greenhouse, truth.get());
      if (!params_.truth_file.empty() && !writeGreenhouseTruth(*truth, params_.truth_file)) {
        ROS_FATAL("thorvald_sim: cannot write ~truth_file %s", params_.truth_file.c_str());
        return false;
      }
      floor_z_ = [truth](double x, double y) { return truth->floorHeightAt(x, y); };
      spawn_lift_ = [truth](double x, double y) { return x < truth->edge_x ? truth->floorHeightAt(x, y) : 0.0; };
      return addActors(world, truth.get());
    } else {
      CottonRowTruth truth;
      *world = makeCottonRowWorld(params_.cotton_row, &truth);
      if (!params_.truth_file.empty() && !writeCottonRowTruth(truth, params_.truth_file)) {
        ROS_FATAL("thorvald_sim: cannot write ~truth_file %s", params_.truth_file.c_str());
        return false;
      }
    }
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("thorvald_sim: world %s: parameter %s", params_.world.c_str(), e.what());
    return false;
  }
  return addActors(world, nullptr);
}

bool SimRos::addActors(WorldDescription* world, const GreenhouseTruth* truth) {
  if (!params_.actors.valid()) return true;
  try {
    actors_ = std::make_unique<ActorScripts>(parseActors(params_.actors, truth));
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("thorvald_sim: %s", e.what());
    return false;
  } catch (const XmlRpc::XmlRpcException& e) {
    ROS_FATAL("thorvald_sim: ~actors: %s", e.getMessage().c_str());
    return false;
  }
  world->worldbody += actorBodies(*actors_, floor_z_);
  ROS_INFO("thorvald_sim: %zu actors", actors_->size());
  return true;
}

bool SimRos::loadRobots(const WorldDescription& world) {
  // ~robots: list of {namespace, x, y, z, yaw, sensors, encoders}; default: one robot in the node's namespace.
  XmlRpc::XmlRpcValue& list = params_.robots;
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    ROS_FATAL("thorvald_sim: ~robots: expected a list of {namespace, x, y, yaw, sensors}");
    return false;
  }
  std::vector<RobotSpawn> spawns;
  std::vector<std::string> prefixes;
  std::vector<std::vector<SensorConfig>> sensors;
  std::vector<bool> physics;
  for (int i = 0; i < list.size(); ++i) {
    const std::string where = "~robots[" + std::to_string(i) + "]";
    try {
      XmlRpc::XmlRpcValue& r = list[i];
      if (r.getType() != XmlRpc::XmlRpcValue::TypeStruct)
        throw std::invalid_argument("expected a map {namespace, x, y, z, yaw, sensors, encoders}, found " +
                                    thorvald_common::describeParamValue(r));
      for (const auto& member : r) {
        static const std::vector<std::string> known = {"namespace", "x", "y", "z", "yaw", "sensors", "encoders"};
        if (std::find(known.begin(), known.end(), member.first) == known.end())
          throw std::invalid_argument("unknown key '" + member.first + "' (known: namespace, x, y, z, yaw, sensors, " +
                                      "encoders)");
      }
      RobotSpawn s;
      s.name = xmlText(r, "namespace", "");
      s.x = xmlNumber(r, "x", 0), s.y = xmlNumber(r, "y", 0), s.z = xmlNumber(r, "z", 0.02);
      s.yaw = xmlNumber(r, "yaw", 0);
      s.z += spawn_lift_(s.x, s.y);  // a sloped headland lifts the robot
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
      const std::string sensor_file = xmlText(r, "sensors", "");
      sensors.push_back(sensor_file.empty() ? std::vector<SensorConfig>{} : loadSensorConfigFile(sensor_file));
      const std::string encoders = xmlText(r, "encoders", params_.encoders);
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
    SceneOptions options = sceneOptions(params_.sphere_wheels, sensors);
    options.ground = groundUnderWheels(params_.ground, world.name, sensors);
    ROS_INFO("thorvald_sim: ground %s", groundName(options.ground));
    sim_ = std::make_unique<Simulation>(composeScene(world, spawns, options), spawns);
    world_truth_ =
        std::make_unique<WorldTruth>(nh_, *sim_, actors_ ? std::move(*actors_) : ActorScripts(std::vector<ActorSpec>{}),
                                     floor_z_, params_.world_frame, params_.actors_give_way_s);
    actors_.reset();
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
  updater_.add("contacts", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { world_truth_->diagnose(stat); });
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
  world_truth_->moveActors(sim_->time());
  sim_->step(steps_per_period_);
  rosgraph_msgs::Clock c;
  c.clock = ros::Time(sim_->time());
  clock_pub_.publish(c);
  for (auto& r : robots_) r->publish(c.clock, 1.0 / params_.ground_truth_rate_hz);
  world_truth_->publish(c.clock, 1.0 / params_.ground_truth_rate_hz);
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
      // Pace simulated time against the wall clock. A simulation that fell behind (a busy machine) goes on at the
      // requested pace from where it is instead of running flat out to catch up: such a burst outruns the nodes on
      // its clock, whose inputs then age by whole timeouts in simulated time (a mission saw its odometry as lost).
      const ros::WallTime due = wall_start + ros::WallDuration((sim_->time() - sim_start) / params_.real_time_factor);
      if (due > now) {
        (due - now).sleep();
      } else if ((now - due).toSec() > kMaxCatchUpS) {
        wall_start = now;
        sim_start = sim_->time();
      }
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
    for (uint32_t i = 0; i < req.steps; ++i) {
      world_truth_->moveActors(sim_->time());
      sim_->step(1);
    }
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(sim_->time());
    clock_pub_.publish(c);
    for (auto& r : robots_) r->publish(c.clock, 1.0 / params_.ground_truth_rate_hz);
    world_truth_->publish(c.clock, 1.0 / params_.ground_truth_rate_hz);
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
