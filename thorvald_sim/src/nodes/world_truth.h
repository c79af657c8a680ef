#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "thorvald_sim/actors.h"
#include "thorvald_sim/contacts.h"
#include "thorvald_sim/simulation.h"

namespace thorvald_sim {

/// The world's truth for scorers: moves the actors' mocap bodies before each step, publishes their poses on
/// `sim/actors` and every robot body contact on `sim/contacts`, and counts the contacts for diagnostics. Never read
/// by the robots' nodes. Called from the simulator's one thread only.
class WorldTruth {
 public:
  /// `floor_z(x, y)`: the floor under an actor [m].
  WorldTruth(ros::NodeHandle nh, Simulation& sim, ActorScripts actors, std::function<double(double, double)> floor_z,
             const std::string& world_frame, double give_way_s);
  /// Puts the actors where they are at simulated time `t` [s] (before stepping): on their scripts, each standing while
  /// its next step would take it within 0.3 m of a robot, stepping back after give_way_s of it (ActorClocks).
  void moveActors(double t);
  /// After stepping: contact events, and the actors' poses when due.
  void publish(const ros::Time& now, double actor_period_s);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const;

 private:
  Simulation& sim_;
  ActorScripts actors_;
  ActorClocks clocks_;  ///< the actors yield to robots
  std::function<double(double, double)> floor_z_;
  std::string world_frame_;
  std::vector<int> mocap_;  ///< actor -> mocap index
  ContactMonitor contacts_;
  ros::Publisher actors_pub_, contacts_pub_;
  double next_actors_s_ = 0.0;
};

}  // namespace thorvald_sim
