#pragma once

#include <string>
#include <vector>

namespace greenhouse_rail_nav {

/// One input of the UV interlock: what it is called in diagnostics and how old its last message may be.
struct InterlockInputSpec {
  std::string name;        ///< "on rails", "people present", ... (diagnostics name it when it keeps the lamps off)
  double timeout_s = 0.3;  ///< older than this it is stale, and a stale input keeps the lamps off; 0: never stale [s]
};

/// What the interlock decided at one time.
struct InterlockDecision {
  bool lamps_on = false;
  std::vector<std::string> blocking;  ///< "<input>: <why>" for every input keeping the lamps off
};

/// The UV interlock, independent of the mission: the lamps may be on only while every input permits it, each input
/// heard and fresh. Inputs are registered once (add()); their messages are reported with update() as "permits" or not
/// with a short reason. Times are seconds of one clock (ROS time in the node, a simulated clock in tests). Holds no
/// state besides the inputs' last reports, so a decision depends only on them and the time it is taken at.
class UvInterlock {
 public:
  /// Registers an input; returns its index for update(). Throws std::invalid_argument for a negative timeout.
  size_t add(const InterlockInputSpec& spec);
  /// The input's latest message: whether it permits the lamps, and why not (shown while it blocks).
  void update(size_t input, bool permits, double now_s, const std::string& why_not = "");
  InterlockDecision decide(double now_s) const;
  size_t size() const { return inputs_.size(); }
  const InterlockInputSpec& spec(size_t input) const { return inputs_.at(input).spec; }

 private:
  struct Input {
    InterlockInputSpec spec;
    bool heard = false, permits = false;
    double last_s = 0.0;
    std::string why_not;
  };
  std::vector<Input> inputs_;
};

/// Whether a forward speed [m/s] counts as treatment speed: |speed| within tolerance of the treatment speed (the
/// lamps may be on in either direction along the rails).
bool atTreatmentSpeed(double speed_mps, double treat_speed_mps, double tolerance_mps);

/// The interlock's treatment-speed input with hysteresis: it permits once |speed| comes within `on_tolerance` of the
/// treatment speed and keeps permitting until |speed| leaves `tolerance` (on_tolerance <= tolerance), so a speed
/// wavering at the band's edge does not switch the relay off and on. Only the speed input holds: every other input
/// (person, lock, people_present, rails, staleness) still switches the lamps off at once.
class SpeedWindow {
 public:
  /// Throws std::invalid_argument unless 0 <= on_tolerance <= tolerance.
  SpeedWindow(double treat_speed_mps, double tolerance_mps, double on_tolerance_mps);
  /// The latest speed [m/s] (either direction); returns whether it permits the lamps. NaN or inf never permits.
  bool update(double speed_mps);
  bool permits() const { return permits_; }

 private:
  double treat_mps_, tolerance_mps_, on_tolerance_mps_;
  bool permits_ = false;
};

}  // namespace greenhouse_rail_nav
