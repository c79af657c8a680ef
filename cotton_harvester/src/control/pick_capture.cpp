#include "cotton_harvester/control/pick_capture.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cotton_harvester {
namespace control {

std::string PickCaptureParams::check() const {
  if (!(capture_radius_m > 0.0 && capture_radius_m < 1.0)) return "capture_radius_m: expected in (0, 1) [m]";
  if (!(pick_time_s >= 0.0 && pick_time_s < 60.0)) return "pick_time_s: expected in [0, 60) [s]";
  return "";
}

PickCapture::PickCapture(const PickCaptureParams& params) : params_(params) {
  if (const std::string bad = params.check(); !bad.empty()) throw std::invalid_argument("pick capture: " + bad);
}

int PickCapture::addBoll(const Point3& centre) {
  bolls_.push_back(Boll{centre, 0.0, false});
  return static_cast<int>(bolls_.size()) - 1;
}

std::vector<int> PickCapture::update(const Point3& intake, bool vacuum_on, double dt_s) {
  std::vector<int> taken_now;
  const bool sound = std::isfinite(intake.x) && std::isfinite(intake.y) && std::isfinite(intake.z) &&
                     std::isfinite(dt_s) && dt_s > 0.0;
  for (size_t i = 0; i < bolls_.size(); ++i) {
    Boll& boll = bolls_[i];
    if (boll.taken) continue;
    const double distance = sound ? std::sqrt((intake.x - boll.centre.x) * (intake.x - boll.centre.x) +
                                              (intake.y - boll.centre.y) * (intake.y - boll.centre.y) +
                                              (intake.z - boll.centre.z) * (intake.z - boll.centre.z))
                                  : INFINITY;
    if (!vacuum_on || !(distance <= params_.capture_radius_m)) {
      boll.dwell_s = 0.0;  // a break starts the pick over
      continue;
    }
    boll.dwell_s += dt_s;
    if (boll.dwell_s + 1e-9 >= params_.pick_time_s) {
      boll.taken = true;
      taken_now.push_back(static_cast<int>(i));
    }
  }
  return taken_now;
}

bool PickCapture::taken(int index) const {
  return index >= 0 && index < static_cast<int>(bolls_.size()) && bolls_[index].taken;
}

int PickCapture::remaining() const {
  return static_cast<int>(std::count_if(bolls_.begin(), bolls_.end(), [](const Boll& b) { return !b.taken; }));
}

}  // namespace control
}  // namespace cotton_harvester
