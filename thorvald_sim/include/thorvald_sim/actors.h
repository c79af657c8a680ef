#pragma once

#include <functional>
#include <string>
#include <vector>

namespace thorvald_sim {

/// What an actor is: a person (upright capsule) or a trolley (box on the floor).
enum class ActorKind { kPerson, kTrolley };

/// A point of an actor's path: where it is [m] at simulated time t [s]. Two waypoints at the same place with
/// different times make it stand there.
struct ActorWaypoint {
  double x = 0, y = 0, t = 0;
};

/// One actor: a kinematic body moved by the simulator along a scripted path or a seeded random walk. Its pose is
/// truth for scorers only; the robots' sensors see its body like any other.
struct ActorSpec {
  std::string name;
  ActorKind kind = ActorKind::kPerson;
  std::vector<ActorWaypoint> path;  ///< times increasing; before the first it stands at the first, after the last
                                    ///< at the last (or starts over if `loop`: the path should end where it begins)
  bool loop = false;
  /// Random walk instead of a path (path empty): from a random point of the region it walks at `speed_mps` to
  /// random points of the region and stands `pause_s` at each; the same seed gives the same walk.
  bool random_walk = false;
  double region[4] = {0, 0, 0, 0};  ///< x_min, x_max, y_min, y_max [m]
  double speed_mps = 1.0;
  double pause_s = 2.0;
  unsigned seed = 1;
  /// Started by a robot: until a robot's body comes within `trigger_radius_m` of (trigger_x, trigger_y) the actor
  /// stands at the start of its script, and its clock runs from then on (once: it does not wait again). A scenario
  /// that needs a person to step in front of a moving robot places them by the robot, not by the clock. 0: no
  /// trigger, the script runs from the start of the simulation.
  double trigger_x = 0, trigger_y = 0, trigger_radius_m = 0;
  double radius_m = 0.25;  ///< person: capsule radius [m]; trolley: half width
  double height_m = 1.75;  ///< [m]
  double length_m = 1.0;   ///< trolley: length along its heading [m]
};

/// An actor's pose at one time: position on the floor [m], heading [rad] (along its motion, kept while standing).
struct ActorPose {
  double x = 0, y = 0, z = 0, yaw = 0;
};

/// Moves the actors: pose of each at a simulated time. A random walk is drawn once, up to `walk_horizon_s`, then
/// repeats. Throws std::invalid_argument naming the actor and what is wrong.
class ActorScripts {
 public:
  explicit ActorScripts(std::vector<ActorSpec> specs, double walk_horizon_s = 3600.0);
  size_t size() const { return specs_.size(); }
  const ActorSpec& spec(size_t i) const { return specs_[i]; }
  /// Pose of actor `i` at time `t` [s]; z stays 0 (the caller puts it on its floor).
  ActorPose poseAt(size_t i, double t) const;

 private:
  std::vector<ActorSpec> specs_;
};

/// The actors' own clocks: a person does not walk into a machine, even one that stopped for them. Each actor runs its
/// script (path or random walk) on a clock of its own that stands still while its next step would take it nearer
/// than `clearance_m` to a robot's body (and nearer than it is); it walks on as soon as the way is free, or when the
/// step takes it away. Without robots in the way the clocks are the simulated time. A person who has stood
/// `give_way_s` without a break gives way: their clock runs backwards for `step_back_s` (they step back the way they
/// came), then forwards again (a robot that stopped because of them, beside its lamps, can go on; 0: they wait for
/// good).
class ActorClocks {
 public:
  explicit ActorClocks(const ActorScripts& scripts, double clearance_m = 0.3, double give_way_s = 0.0,
                       double step_back_s = 5.0)
      : scripts_(scripts),
        clearance_m_(clearance_m),
        give_way_s_(give_way_s),
        step_back_s_(step_back_s),
        clock_(scripts.size(), 0.0),
        waited_(scripts.size(), 0.0),
        standing_(scripts.size(), 0.0),
        back_left_(scripts.size(), 0.0),
        triggered_(scripts.size(), false) {}
  /// Distance on the floor from a point to the nearest robot body [m] (infinite: none).
  using RobotGap = std::function<double(double x, double y)>;
  /// Moves every clock from the last call's time to `t` [s] (the first call starts them at `t`); returns the actors'
  /// poses.
  std::vector<ActorPose> advance(double t, const RobotGap& gap_to_robots);
  /// How long actor `i` has stood waiting for a robot [s].
  double waited(size_t i) const { return waited_.at(i); }
  /// Whether actor `i` runs its script: it has no trigger, or a robot has set it off.
  bool running(size_t i) const { return scripts_.spec(i).trigger_radius_m <= 0.0 || triggered_.at(i); }

 private:
  const ActorScripts& scripts_;
  double clearance_m_, give_way_s_, step_back_s_;
  std::vector<double> clock_, waited_;
  std::vector<double> standing_;   ///< [s] stood without a break
  std::vector<double> back_left_;  ///< [s] of stepping back still to go
  std::vector<double> start_;      ///< each clock's first time (stepping back stops there)
  std::vector<bool> triggered_;    ///< a robot has set off the actor's trigger
  double last_t_ = 0.0;
  bool started_ = false;
};

/// Body name of an actor in the MuJoCo model ("actor_<name>"); its one geom has the same name.
std::string actorBodyName(const std::string& actor_name);

/// The actors as MJCF mocap bodies (children of <worldbody>) at their poses at t = 0; `floor_z(x, y)` gives the
/// floor under them [m].
std::string actorBodies(const ActorScripts& actors, const std::function<double(double, double)>& floor_z);

}  // namespace thorvald_sim
