#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace thorvald_sim {

/// A body contact that began or ended: a robot's body touching something that is not the ground under a wheel.
struct ContactEvent {
  bool start = true;       ///< true: began; false: ended
  std::string robot;       ///< the robot's namespace
  std::string robot_body;  ///< its body (e.g. "r1/base_link")
  std::string other;       ///< the other robot's body, an actor's body, or the world geom touched
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< where (the first contact point; at the end: the last) [m]
  double time = 0.0;                                   ///< simulated time of the event [s]
  double start_time = 0.0;                             ///< when the contact began [s]
};

/// Distance on the floor from (x, y) to the nearest geom of the bodies under the root bodies `roots` [m] (infinite:
/// none): each geom as its box in its own frame (ellipsoids, capsules and cylinders by their bounding boxes, meshes
/// and others as their bounding spheres), the point taken at the geom centre's height. ActorClocks' gap to the robots.
double floorGapToBodies(const mjModel* m, const mjData* d, const std::vector<int>& roots, double x, double y);

/// Watches MuJoCo's contacts and reports each robot body contact once when it begins and once when it ends. A wheel
/// (`wheel_link<i>`, casters, passive wheels) on the ground is normal driving and not reported: the ground is every
/// world geom named row_ground*, headland_floor*, headland_bump*, floor*, rail*, rusty_rail* or hose*. Contacts
/// between bodies of one robot are not reported. Checks the contacts present when called (call once per control
/// period): a touch that begins and ends between two calls is missed.
class ContactMonitor {
 public:
  /// `robot_roots`: each robot's root body id and its namespace.
  ContactMonitor(const mjModel* model, const std::vector<std::pair<int, std::string>>& robot_roots);
  /// Compares the contacts in `data` with those of the last call; returns the contacts that began and ended.
  std::vector<ContactEvent> update(const mjData* data);
  /// Contacts begun so far.
  unsigned long started() const { return started_; }
  /// Contacts going on now.
  size_t active() const { return active_.size(); }

 private:
  struct Ongoing {
    ContactEvent event;
    bool seen = false;
  };
  const mjModel* m_;
  std::vector<int> robot_of_body_;  ///< body -> robot index, -1 for the world and actors
  std::vector<char> wheel_body_, ground_geom_;
  std::vector<std::string> robot_names_;
  std::map<std::pair<int, std::string>, Ongoing> active_;  ///< (robot body, other) -> the contact
  unsigned long started_ = 0;
  std::string otherName(int geom) const;
};

}  // namespace thorvald_sim
