#pragma once

#include <string>
#include <vector>

#include "cotton_harvester/control/harvest_decision.h"

namespace cotton_harvester {
namespace control {

/// When the vacuum end-effector takes a boll.
struct PickCaptureParams {
  double capture_radius_m = 0.04;  ///< the boll's centre within this of the end-effector's intake [m]
  double pick_time_s = 0.8;        ///< with the vacuum on, this long without a break [s]

  /// Empty when sound, otherwise "key: expected ...".
  std::string check() const;
};

/// Decides picks from what the arm did, for a simulated rover: each boll is taken when the end-effector's intake
/// stays within the capture radius of it, with the vacuum on, for the pick time without a break; it then leaves
/// the world. Fed by events in time order (end-effector position, vacuum state, time step), not by a success
/// probability. Positions in one fixed frame (e.g. the row's) [m]. Not thread-safe.
class PickCapture {
 public:
  explicit PickCapture(const PickCaptureParams& params = PickCaptureParams());

  /// Adds a boll on its plant; returns its index.
  int addBoll(const Point3& centre);
  /// One step of dt [s] (> 0, finite) with the end-effector's intake at `intake` and the vacuum on or off.
  /// Returns the indices of the bolls taken during this step. Non-finite input is ignored (nothing taken, dwell
  /// timers reset).
  std::vector<int> update(const Point3& intake, bool vacuum_on, double dt_s);

  bool taken(int index) const;
  int remaining() const;
  int present() const { return static_cast<int>(bolls_.size()); }

 private:
  struct Boll {
    Point3 centre;
    double dwell_s = 0.0;
    bool taken = false;
  };
  PickCaptureParams params_;
  std::vector<Boll> bolls_;
};

}  // namespace control
}  // namespace cotton_harvester
