#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <memory>
#include <string>
#include <vector>

#include "robot_io.h"
#include "world_truth.h"
#include "thorvald_sim/Step.h"
#include "thorvald_sim/simulation.h"
#include "thorvald_sim/world.h"

namespace thorvald_sim {

/// Parameters of the thorvald_sim node (see README).
struct SimNodeParams {
  std::string world = "flat";
  std::string truth_file;  ///< where the world's ground truth is written ("" : nowhere)
  std::string world_frame = "map";
  double real_time_factor = 1.0;   ///< 0: as fast as possible
  double control_period_s = 0.01;  ///< /clock and joint targets advance in these steps [s]
  double ground_truth_rate_hz = 50.0;
  bool publish_map_tf = false;
  bool sphere_wheels = true;  ///< SceneOptions::sphere_wheels: false keeps the wheels' URDF cylinders
  /// The surface under every wheel (terrain.h): a name, or `auto` for the world's surface in the sensors' profile
  /// (wet concrete in the greenhouse, loose soil in the cotton row when a sensor file says `datasheet`).
  std::string ground = "dry_concrete";
  bool start_paused = false;
  double wait_for_description_s = 30.0;
  std::string encoders = "joint_simulator";  ///< default of the robots' `encoders`
  XmlRpc::XmlRpcValue robots;                ///< ~robots, or one robot from ~x, ~y, ~yaw, ~sensors
  double flat_half_size_m = 100.0;
  GreenhouseParams greenhouse;
  CottonRowParams cotton_row;
  XmlRpc::XmlRpcValue actors;       ///< ~actors (see world_params.h); none if unset
  double actors_give_way_s = 15.0;  ///< ~actors_give_way: a person kept waiting this long steps back (0: never) [s]
};

/// The simulator node: one MuJoCo world with every robot, stepped on one thread that also serves callbacks.
class SimRos {
 public:
  SimRos(ros::NodeHandle nh, ros::NodeHandle pnh);
  /// Loads parameters, builds the world and robots. False (with a logged reason) if it cannot.
  bool start();
  /// Runs until shutdown.
  void run();

 private:
  bool loadParams();
  bool buildWorld(WorldDescription* world);
  bool loadRobots(const WorldDescription& world);
  void advance();
  bool onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onStep(Step::Request& req, Step::Response& res);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  /// Adds the actors' bodies to the world; false (logged) on a bad ~actors.
  bool addActors(WorldDescription* world, const GreenhouseTruth* truth);

  ros::NodeHandle nh_, pnh_;
  SimNodeParams params_;
  CameraRenderer& renderer();

  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<CameraRenderer> renderer_;  ///< created when a camera is first watched
  std::vector<std::unique_ptr<RobotIo>> robots_;
  std::function<double(double, double)> floor_z_ = [](double, double) { return 0.0; };     ///< under actors, robots
  std::function<double(double, double)> spawn_lift_ = [](double, double) { return 0.0; };  ///< headland slope [m]
  std::unique_ptr<ActorScripts> actors_;     ///< until world_truth_ takes them
  std::unique_ptr<WorldTruth> world_truth_;  ///< actors and contacts
  ros::Publisher clock_pub_;
  ros::ServiceServer pause_srv_, unpause_srv_, reset_srv_, step_srv_;
  diagnostic_updater::Updater updater_;
  bool paused_ = false;
  int steps_per_period_ = 5;
  double achieved_rtf_ = 0.0;
};

}  // namespace thorvald_sim
