#include "thorvald_navigation/fusion_monitor.h"

#include <algorithm>
#include <sstream>

namespace thorvald_navigation {

std::string FusionHealth::summary() const {
  if (reasons.empty()) return "fusing";
  std::string s;
  for (const std::string& r : reasons) s += (s.empty() ? "" : "; ") + r;
  return s;
}

void FusionMonitor::addInput(const std::string& name, double timeout_s, bool required) {
  Input in;
  in.timeout_s = timeout_s;
  in.required = required;
  inputs_[name] = in;
}

void FusionMonitor::received(const std::string& name, double t, bool valid, const std::string& why) {
  auto it = inputs_.find(name);
  if (it == inputs_.end()) return;
  Input& in = it->second;
  in.seen = true;
  in.valid = valid;
  in.invalid_why = why;
  if (valid) in.last_t = t;
}

void FusionMonitor::fused(const std::string& name) {
  auto it = inputs_.find(name);
  if (it != inputs_.end()) it->second.refused = false;
}

void FusionMonitor::refused(const std::string& name, const std::string& why) {
  auto it = inputs_.find(name);
  if (it == inputs_.end()) return;
  it->second.refused = true;
  it->second.refused_why = why;
  ++it->second.refusals;
}

FusionHealth FusionMonitor::evaluate(double now) const {
  FusionHealth h;
  auto fail = [&](const Input& in, const std::string& why) {
    h.reasons.push_back(why);
    const FusionHealth::Level l = in.required ? FusionHealth::kError : FusionHealth::kWarn;
    h.level = std::max(h.level, l);
    if (in.required) h.localization_ok = false;
  };
  for (const auto& [name, in] : inputs_) {
    std::ostringstream why;
    if (!in.seen) {
      if (now - start_ > in.timeout_s) {
        why << name << ": nothing received since start";
        fail(in, why.str());
      }
      continue;
    }
    const double age = in.valid || in.last_t > 0.0 ? now - in.last_t : now - start_;
    if (!in.valid) {
      why << name << ": " << (in.invalid_why.empty() ? "no usable data" : in.invalid_why);
      fail(in, why.str());
    } else if (age > in.timeout_s) {
      why.precision(3);
      why << name << ": nothing for " << age << " s (timeout " << in.timeout_s << " s)";
      fail(in, why.str());
    } else if (in.refused) {
      why << name << ": last measurement refused (" << in.refused_why << ")";
      fail(in, why.str());
    }
  }
  return h;
}

}  // namespace thorvald_navigation
