#include "greenhouse_rail_nav/uv_interlock.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace greenhouse_rail_nav {

size_t UvInterlock::add(const InterlockInputSpec& spec) {
  if (!(spec.timeout_s >= 0.0)) {
    throw std::invalid_argument("interlock input '" + spec.name + "': timeout must be >= 0 s (0: never stale)");
  }
  Input in;
  in.spec = spec;
  inputs_.push_back(in);
  return inputs_.size() - 1;
}

void UvInterlock::update(size_t input, bool permits, double now_s, const std::string& why_not) {
  Input& in = inputs_.at(input);
  in.heard = true;
  in.permits = permits;
  in.last_s = now_s;
  in.why_not = permits ? "" : (why_not.empty() ? "does not permit" : why_not);
}

InterlockDecision UvInterlock::decide(double now_s) const {
  InterlockDecision d;
  for (const auto& in : inputs_) {
    if (!in.heard) {
      d.blocking.push_back(in.spec.name + ": never received");
    } else if (in.spec.timeout_s > 0.0 && now_s - in.last_s > in.spec.timeout_s) {
      char buf[96];
      std::snprintf(buf, sizeof(buf), ": stale (last %.2f s ago, timeout %.2f s)", now_s - in.last_s,
                    in.spec.timeout_s);
      d.blocking.push_back(in.spec.name + buf);
    } else if (!in.permits) {
      d.blocking.push_back(in.spec.name + ": " + in.why_not);
    }
  }
  d.lamps_on = !inputs_.empty() && d.blocking.empty();
  return d;
}

bool atTreatmentSpeed(double speed_mps, double treat_speed_mps, double tolerance_mps) {
  return std::isfinite(speed_mps) && std::fabs(std::fabs(speed_mps) - treat_speed_mps) <= tolerance_mps;
}

SpeedWindow::SpeedWindow(double treat_speed_mps, double tolerance_mps, double on_tolerance_mps)
    : treat_mps_(treat_speed_mps), tolerance_mps_(tolerance_mps), on_tolerance_mps_(on_tolerance_mps) {
  if (!(on_tolerance_mps >= 0.0 && on_tolerance_mps <= tolerance_mps)) {
    throw std::invalid_argument("speed window: the on tolerance must be in [0, tolerance]");
  }
}

bool SpeedWindow::update(double speed_mps) {
  permits_ = atTreatmentSpeed(speed_mps, treat_mps_, permits_ ? tolerance_mps_ : on_tolerance_mps_);
  return permits_;
}

}  // namespace greenhouse_rail_nav
