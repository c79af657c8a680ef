#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "cotton_harvester/control/harvest_decision.h"
#include "cotton_harvester/control/leaf_clearance.h"

namespace cotton_harvester {
namespace control {

/// Result of one action of the rover or the arm.
enum class MoveResult { kDone, kFailed, kPreempted };

/// A pose of the arm: the horizontal axis' extension [m] and the depth [m] of the end-effector housing's top face
/// below the camera. NaN: that axis stays where it is.
struct ArmPose {
  double extension_m = std::numeric_limits<double>::quiet_NaN();
  double depth_m = std::numeric_limits<double>::quiet_NaN();
};

/// The organised cloud of the frame last observed and the focal length [px] of the camera it came from. `view`
/// points into memory that `keep` holds (or, with `keep` empty, that the plant holds until its next frame).
struct CameraCloud {
  CloudView view;
  double fx_px = 0.0;
  std::shared_ptr<const void> keep;
};

/// What the harvest machine and its manoeuvres (HarvestActions) drive: the camera, the rover, the arm's two axes
/// and the vacuum, as primitives with no decisions in them. The harvest_state_machine node implements it on topics
/// (TopicHarvestPlant), the simulator in process (SimHarvestPlant), tests with scripts. Every blocking call returns
/// promptly (kPreempted / nullopt) once `preempted()` turns true.
class HarvestPlant {
 public:
  using Preempted = std::function<bool()>;
  virtual ~HarvestPlant() = default;
  /// A camera frame taken after the last action finished; nullopt on timeout or preemption.
  virtual std::optional<HarvestObservation> observe(const Preempted& preempted) = 0;
  /// Moves the rover by `distance_m` along the row (negative: back) while the arm goes to `arm` (NaN axes stay),
  /// and waits until the rover settled and the arm arrived.
  virtual MoveResult moveRover(double distance_m, const ArmPose& arm, const Preempted& preempted) = 0;
  /// Moves the arm's axes to `target` (NaN axes stay) and waits until they arrived.
  virtual MoveResult moveArm(const ArmPose& target, const Preempted& preempted) = 0;
  /// Where the arm's axes are now (their counters or joint states); nullopt while not known.
  virtual std::optional<ArmPose> armPose() const = 0;
  /// The vacuum (the brush on the paper's rover) on or off.
  virtual void setVacuum(bool on) = 0;
  /// Lets `seconds` of the plant's time pass; kPreempted when preempted meanwhile.
  virtual MoveResult wait(double seconds, const Preempted& preempted) = 0;
  /// The cloud of the frame last observed; nullopt when there is none (not received in time, or preempted).
  virtual std::optional<CameraCloud> lastCloud(const Preempted& preempted) = 0;
  /// Time [s] and the rover's position along the row [m].
  virtual double now() const = 0;
  virtual double roverPositionM() const = 0;
  /// Why the last primitive that failed did (a frame or a rover position that did not come, a move that did not
  /// arrive), for the machine's abort reason; empty when the plant does not tell.
  virtual std::string lastFailure() const { return {}; }
};

}  // namespace control
}  // namespace cotton_harvester
