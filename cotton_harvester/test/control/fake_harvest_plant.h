#pragma once

// A HarvestPlant for tests that records every primitive call, moves an ideal arm and rover, answers frames from a
// script and shows a synthetic organised cloud (ground and flat leaves) to the manoeuvres that ask for one.

#include <cmath>
#include <cstring>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cotton_harvester/control/harvest_plant.h"

namespace cotton_harvester {
namespace control {
namespace fake {

/// A flat patch of foliage in the camera frame [m]: x across, y along the row, at depth z.
struct Leaf {
  double x_min, x_max, y_min, y_max, z;
};

/// An organised cloud (w x h, focal length fx, principal point at the centre) of the ground at `ground_z` and the
/// leaves, the shallowest where they overlap.
inline std::shared_ptr<std::vector<float>> makeCloud(const std::vector<Leaf>& leaves, CloudView* view,
                                                     double ground_z = 2.2, int w = 640, int h = 360,
                                                     double fx = 350.0) {
  auto data = std::make_shared<std::vector<float>>(static_cast<std::size_t>(3 * w * h));
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const double rx = (u - 0.5 * w) / fx, ry = (v - 0.5 * h) / fx;
      double z = ground_z;
      for (const Leaf& l : leaves)
        if (l.z < z && rx * l.z >= l.x_min && rx * l.z <= l.x_max && ry * l.z >= l.y_min && ry * l.z <= l.y_max)
          z = l.z;
      float* p = data->data() + 3 * (static_cast<std::size_t>(v) * w + u);
      p[0] = static_cast<float>(rx * z);
      p[1] = static_cast<float>(ry * z);
      p[2] = static_cast<float>(z);
    }
  view->data = reinterpret_cast<const std::uint8_t*>(data->data());
  view->rows = h;
  view->cols = w;
  view->point_step = 12;
  view->row_step = 12 * static_cast<std::size_t>(w);
  return data;
}

class FakeHarvestPlant : public HarvestPlant {
 public:
  /// One primitive call: "observe", "rover" (a: distance, b: -), "arm" (a: extension, b: depth; NaN: stays),
  /// "vacuum" (a: 1 on, 0 off), "wait" (a: seconds), "cloud".
  struct Call {
    Call(std::string what_, double a_ = std::nan(""), double b_ = std::nan(""), ArmPose arm_ = ArmPose())
        : what(std::move(what_)), a(a_), b(b_), arm(arm_) {}
    std::string what;
    double a, b;
    ArmPose arm;  ///< "rover": where the arm was sent meanwhile
  };
  std::vector<Call> calls;

  std::deque<std::optional<HarvestObservation>> frames;  ///< empty script: frames without bolls
  std::vector<Leaf> leaves;                              ///< what the cloud shows (empty: bare ground)
  bool has_cloud = true;
  ArmPose arm{0.35, 1.0};
  bool vacuum = false;
  double position = 0.0, time = 0.0;
  MoveResult result = MoveResult::kDone;  ///< of every rover and arm move
  int fail_arm_move = -1;                 ///< the arm move of this index (0: the first) fails
  int arm_moves = 0;
  /// When set, preemption is requested (preempted() of the tests turns true) once this many calls were made.
  std::optional<std::size_t> preempt_after_calls;

  bool preemptRequested() const { return preempt_after_calls && calls.size() >= *preempt_after_calls; }

  std::optional<HarvestObservation> observe(const Preempted& preempted) override {
    calls.push_back({"observe"});
    time += 0.1;
    if (preempted()) return std::nullopt;
    if (frames.empty()) {
      HarvestObservation empty;
      empty.rover_position_m = position;
      return empty;
    }
    auto frame = frames.front();
    frames.pop_front();
    if (frame) frame->rover_position_m = position;
    return frame;
  }
  MoveResult moveRover(double distance_m, const ArmPose& pose, const Preempted& preempted) override {
    calls.push_back({"rover", distance_m, std::nan(""), pose});
    if (preempted()) return MoveResult::kPreempted;
    apply(pose);
    if (result == MoveResult::kDone) position += distance_m;
    time += 1.0;
    return result;
  }
  MoveResult moveArm(const ArmPose& target, const Preempted& preempted) override {
    calls.push_back({"arm", target.extension_m, target.depth_m});
    if (preempted()) return MoveResult::kPreempted;
    time += 0.5;
    if (arm_moves++ == fail_arm_move || result != MoveResult::kDone) return MoveResult::kFailed;
    apply(target);
    return MoveResult::kDone;
  }
  std::optional<ArmPose> armPose() const override { return arm; }
  void setVacuum(bool on) override {
    calls.push_back({"vacuum", on ? 1.0 : 0.0});
    vacuum = on;
  }
  MoveResult wait(double seconds, const Preempted& preempted) override {
    calls.push_back({"wait", seconds});
    time += seconds;
    return preempted() ? MoveResult::kPreempted : MoveResult::kDone;
  }
  std::optional<CameraCloud> lastCloud(const Preempted&) override {
    calls.push_back({"cloud"});
    if (!has_cloud) return std::nullopt;
    CameraCloud cloud;
    cloud.keep = makeCloud(leaves, &cloud.view);
    cloud.fx_px = 350.0;
    return cloud;
  }
  double now() const override { return time; }
  double roverPositionM() const override { return position; }

  /// The calls of one kind, in order.
  std::vector<Call> only(const std::string& what) const {
    std::vector<Call> out;
    for (const auto& c : calls)
      if (c.what == what) out.push_back(c);
    return out;
  }
  /// The names of the calls, in order.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& c : calls) out.push_back(c.what);
    return out;
  }

 protected:
  void apply(const ArmPose& pose) {
    if (std::isfinite(pose.extension_m)) arm.extension_m = pose.extension_m;
    if (std::isfinite(pose.depth_m)) arm.depth_m = pose.depth_m;
  }
};

}  // namespace fake
}  // namespace control
}  // namespace cotton_harvester
