#pragma once

#include <map>
#include <string>
#include <vector>

namespace thorvald_navigation {

/// What the fusion's health is: OK, WARN or ERROR with the reasons, and whether a controller may trust the pose.
struct FusionHealth {
  enum Level { kOk = 0, kWarn = 1, kError = 2 };
  Level level = kOk;
  bool localization_ok = true;       ///< false: a controller should stop rather than guess
  std::vector<std::string> reasons;  ///< one line per problem, empty when OK
  std::string summary() const;       ///< the reasons joined by "; ", or "fusing"
};

/// Watches the inputs of a fusion (each sensor's arrivals, fixes and refusals) and says whether the pose can be
/// trusted. A required input that never arrived, fell silent for longer than its timeout, reports no fix, or whose
/// last measurement the filter refused (a position jump beyond the Mahalanobis gate) makes the health ERROR and
/// localization_ok false; the same on an optional input is a WARN. ROS-free: times are seconds on any clock.
class FusionMonitor {
 public:
  /// Declares an input with its timeout [s] (> 0); `required` inputs stop the rover when they fail.
  void addInput(const std::string& name, double timeout_s, bool required);
  /// A message arrived at `t` [s]; `valid` false with `why` for a message that carries no usable data (no fix).
  void received(const std::string& name, double t, bool valid = true, const std::string& why = "");
  /// The filter fused the input's last measurement.
  void fused(const std::string& name);
  /// The filter refused the input's last measurement (`why`: the gate's distance, a non-finite value).
  void refused(const std::string& name, const std::string& why);
  /// The health at time `now` [s] (started at `start` [s]: an input gets one timeout from the start to arrive).
  FusionHealth evaluate(double now) const;
  void setStart(double t) { start_ = t; }

 private:
  struct Input {
    double timeout_s = 1.0;
    bool required = true;
    bool seen = false;
    double last_t = 0.0;
    bool valid = true;
    std::string invalid_why;
    bool refused = false;
    std::string refused_why;
    long refusals = 0;
  };
  std::map<std::string, Input> inputs_;
  double start_ = 0.0;
};

}  // namespace thorvald_navigation
