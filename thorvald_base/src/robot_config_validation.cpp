// Checks of a robot file's values that parsing and run-time changes share: each drive's ranges, CAN ids, drive
// spacing, observability, implement ids; and the run-time change of one drive key.
#include "thorvald_base/robot_config.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "module_fields.h"

namespace thorvald_base {

void validateDrive(const DriveConfig& d, const std::string& source, const std::string& where) {
  if (d.type != 0 && d.type != 1) {
    throw ConfigError(source, where + ".type", "must be 0 (steering + propulsion) or 1 (propulsion only)");
  }
  // The same ranges as at load time, so a run-time change (set_drive_params) is held to them too.
  for (const auto& field : detail::driveFields()) {
    if (!field.value) continue;
    if (!d.steered() && field.names[0].rfind("str_", 0) == 0) continue;  // unused by a fixed drive
    detail::checkBounds(field.value(d), field.bounds, source, where + "." + field.names[0]);
  }
  if (d.protocol != "thorvald" && d.protocol != "cia402") {
    throw ConfigError(source, where + ".protocol", "must be 'thorvald' or 'cia402', found '" + d.protocol + "'");
  }
}

void validateCanNodeIds(const std::vector<DriveConfig>& drives, const std::string& source) {
  std::map<int, size_t> user;  // node id -> index into drives of the first drive using it
  for (size_t i = 0; i < drives.size(); ++i) {
    const DriveConfig& d = drives[i];
    std::vector<std::pair<int, std::string>> ids = {{d.node, "node id"}};
    if (d.protocol == "cia402" && d.steered()) ids.push_back({d.node + 64, "steering axis id (node + 64)"});
    for (const auto& [id, what] : ids) {
      const auto [it, fresh] = user.emplace(id, i);
      if (fresh) continue;
      const DriveConfig& other = drives[it->second];
      // Two consecutive propulsion-only drives on one two-channel Thorvald controller share its node id.
      const bool channel_pair = it->second + 1 == i && what == "node id" && d.type == 1 && other.type == 1 &&
                                d.protocol == "thorvald" && other.protocol == "thorvald" &&
                                (it->second == 0 || drives[it->second - 1].node != id);
      if (channel_pair) continue;
      throw ConfigError(source, "motor_drives.drive" + std::to_string(d.index) + ".node",
                        "its CAN " + what + " " + std::to_string(id) + " is already used by drive" +
                            std::to_string(other.index) +
                            "; every controller needs its own node id (only two consecutive type-1 drives may share "
                            "one, as the two channels of one controller)");
    }
  }
}

void validateDriveSpacing(const std::vector<DriveConfig>& drives, const std::string& source) {
  for (size_t j = 0; j < drives.size(); ++j) {
    for (size_t i = 0; i < j; ++i) {
      const double gap = std::hypot(drives[j].x - drives[i].x, drives[j].y - drives[i].y);
      const double needed = 0.5 * (drives[i].w_wheel + drives[j].w_wheel);
      if (gap < needed) {
        std::ostringstream s;
        s << "at (" << drives[j].x << ", " << drives[j].y << ") m, only " << gap << " m from drive" << drives[i].index
          << ": the wheels would overlap (expected at least " << needed << " m apart)";
        throw ConfigError(source, "motor_drives.drive" + std::to_string(drives[j].index), s.str());
      }
    }
  }
}

void validateObservability(const std::vector<DriveConfig>& drives, const std::vector<PassiveWheelConfig>& passive,
                           const std::string& source) {
  // Every wheel sees the velocity of its contact point, (vx - wz*y, vy + wz*x), a passive wheel only its sideways
  // part. Odometry needs these equations to determine (vx, vy, wz): the stacked rows must have rank 3.
  double extent = 1.0;
  for (const auto& d : drives) extent = std::max({extent, std::fabs(d.x), std::fabs(d.y)});
  Eigen::MatrixXd rows(2 * drives.size() + passive.size(), 3);
  int r = 0;
  for (const auto& d : drives) {
    rows.row(r++) << 1.0, 0.0, -d.y / extent;
    rows.row(r++) << 0.0, 1.0, d.x / extent;
  }
  for (const auto& p : passive) rows.row(r++) << 0.0, 1.0, p.x / extent;
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(rows).singularValues();
  if (sv.size() < 3 || sv(2) < 1e-6 * sv(0)) {
    throw ConfigError(source, "motor_drives",
                      "the drives (and passive_wheels) leave the robot's motion undetermined: odometry needs at least "
                      "two drives at different places, or one drive and a passive wheel off its axle");
  }
}

void validateImplementCanIds(const std::vector<int>& ids, const std::string& source, const std::string& where) {
  if (ids.size() > kMaxModulesPerGroup) {
    throw ConfigError(source, where,
                      "lists " + std::to_string(ids.size()) + " ids, at most " + std::to_string(kMaxModulesPerGroup) +
                          " are accepted");
  }
  std::set<int> seen;
  for (size_t i = 0; i < ids.size(); ++i) {
    const std::string entry = where + "[" + std::to_string(i) + "]";
    if (ids[i] < 1 || ids[i] > kMaxCanStdId) {
      throw ConfigError(source, entry,
                        "CAN id " + std::to_string(ids[i]) + " outside 0x001..0x7FF (11-bit identifiers; 0 is NMT)");
    }
    if (!seen.insert(ids[i]).second) {
      throw ConfigError(source, entry, "CAN id " + std::to_string(ids[i]) + " is listed twice");
    }
  }
}

bool setDriveKey(DriveConfig& drive, const std::string& key, double value) {
  using D = DriveConfig;
  static const std::map<std::string, double D::*> keys = {
      {"x", &D::x},
      {"y", &D::y},
      {"r_wheel", &D::r_wheel},
      {"w_wheel", &D::w_wheel},
      {"prp_gr_rt", &D::prp_gr_rt},
      {"prp_enc_ppr", &D::prp_enc_ppr},
      {"prp_max_rpm", &D::prp_max_rpm},
      {"prp_sim_a", &D::prp_sim_a},
      {"str_gr_rt", &D::str_gr_rt},
      {"str_enc_ppr", &D::str_enc_ppr},
      {"str_lim", &D::str_lim},
      {"str_llm", &D::str_lim},
      {"str_sim_v", &D::str_sim_v},
      {"str_stm_v", &D::str_sim_v},
  };
  const auto it = keys.find(key);
  if (it == keys.end() || !std::isfinite(value)) return false;
  drive.*(it->second) = value;
  return true;
}

}  // namespace thorvald_base
