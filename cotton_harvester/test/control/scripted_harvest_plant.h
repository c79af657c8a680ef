#pragma once

// Plants for the HarvestMachine tests: frames from a script (on fake::FakeHarvestPlant), leaves to look under, and a
// simulated row with ideal motion.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cotton_harvester/control/harvest_plant.h"
#include "cotton_harvester/control/virtual_row.h"
#include "fake_harvest_plant.h"

namespace cotton_harvester {
namespace control {
namespace fake {

/// A plant whose frames come from a script (FakeHarvestPlant); it records the machine's actions as the
/// primitives show them: "rover" (distance), "arm" (a depth-only move of the arm, to that depth), "pick" (vacuum on,
/// with the extension's offset from where the arm went out from) and "sweep" (a layer to sweep under the leaves).
class ScriptedPlant : public FakeHarvestPlant {
 public:
  std::vector<std::string> actions;
  std::vector<double> values;
  bool block_rover = false;  ///< moveRover waits until preempted
  std::atomic<bool> blocking{false};

  MoveResult moveRover(double distance_m, const ArmPose& arm, const Preempted& preempted) override {
    actions.push_back("rover");
    values.push_back(distance_m);
    if (block_rover) {
      blocking = true;
      while (!preempted()) std::this_thread::yield();
      return MoveResult::kPreempted;
    }
    return FakeHarvestPlant::moveRover(distance_m, arm, preempted);
  }
  MoveResult moveArm(const ArmPose& target, const Preempted& preempted) override {
    if (sweep_moves_ > 0) {
      --sweep_moves_;
    } else if (std::isfinite(target.extension_m)) {
      out_from_ = arm.extension_m;
    } else if (std::isfinite(target.depth_m)) {
      actions.push_back("arm");
      values.push_back(target.depth_m);
    }
    return FakeHarvestPlant::moveArm(target, preempted);
  }
  void setVacuum(bool on) override {
    if (on) {
      actions.push_back("pick");
      values.push_back(arm.extension_m - out_from_);
    }
    FakeHarvestPlant::setVacuum(on);
  }

 protected:
  int sweep_moves_ = 0;  ///< arm moves of a sweep still to come (not the machine's)
  double out_from_ = 0.0;
};

/// A scripted plant with leaves to sweep where `sweep_at` holds its position (to 1 mm), once per place: the cloud
/// shows a leaf in the arm's strip there until it was swept; after the first sweep the frames show `revealed` (what
/// lay under the leaf) until the next pick.
class SearchingPlant : public ScriptedPlant {
 public:
  std::vector<double> sweep_at;
  std::vector<double> searched_at;  ///< places where the search looked at a cloud
  std::optional<HarvestObservation> revealed;

  std::optional<HarvestObservation> observe(const Preempted& preempted) override {
    auto observation = ScriptedPlant::observe(preempted);
    if (showing_ && observation && observation->bolls.empty()) {
      observation = showing_;
      observation->rover_position_m = position;
    }
    return observation;
  }
  void setVacuum(bool on) override {
    if (on) showing_.reset();
    ScriptedPlant::setVacuum(on);
  }
  std::optional<CameraCloud> lastCloud(const Preempted& preempted) override {
    if (searched_at.empty() || std::abs(searched_at.back() - position) > 1e-3) searched_at.push_back(position);
    leaves.clear();
    for (const double s : sweep_at)
      if (std::abs(s - position) < 1e-3 && std::find(swept_.begin(), swept_.end(), s) == swept_.end()) {
        leaves = {{-0.30, -0.18, -0.04, 0.04, 1.40}};
        swept_.push_back(s);
        actions.push_back("sweep");
        sweep_moves_ = 4;
        if (revealed) {
          showing_ = revealed;
          revealed.reset();
        }
      }
    return FakeHarvestPlant::lastCloud(preempted);
  }

 private:
  std::vector<double> swept_;
  std::optional<HarvestObservation> showing_;
};

/// Ideal motion over the simulated row: the rover and the arm go exactly where they are told, the brush runs while
/// the vacuum is on.
class IdealRowPlant : public HarvestPlant {
 public:
  explicit IdealRowPlant(const VirtualRowParams& params) : row(params) {}
  VirtualRow row;
  double travel = 0.0, extension = 0.0, depth = 1.1, time = 0.0;

  std::optional<HarvestObservation> observe(const Preempted&) override {
    time += 0.2;
    HarvestObservation observation;
    observation.bolls = row.visibleBolls(travel);
    observation.end_effector = row.endEffector(extension, depth);
    observation.rover_position_m = travel;
    return observation;
  }
  MoveResult moveRover(double d, const ArmPose& arm, const Preempted& preempted) override {
    travel += d;
    time += 2.0 + std::abs(d) / 0.1;
    return moveArm(arm, preempted);
  }
  MoveResult moveArm(const ArmPose& target, const Preempted&) override {
    time += 1.0;
    if (std::isfinite(target.extension_m)) extension = target.extension_m;
    if (std::isfinite(target.depth_m)) depth = target.depth_m;
    return MoveResult::kDone;
  }
  std::optional<ArmPose> armPose() const override { return ArmPose{extension, depth}; }
  void setVacuum(bool on) override {
    if (on) row.brush(travel, row.endEffector(extension, depth));
  }
  MoveResult wait(double seconds, const Preempted&) override {
    time += seconds;
    return MoveResult::kDone;
  }
  std::optional<CameraCloud> lastCloud(const Preempted&) override { return std::nullopt; }
  double now() const override { return time; }
  double roverPositionM() const override { return travel; }
};

}  // namespace fake
}  // namespace control
}  // namespace cotton_harvester
