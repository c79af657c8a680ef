#include "greenhouse_rail_nav/rail_set_file.h"

#include <cmath>
#include <fstream>

#include <yaml-cpp/yaml.h>

namespace greenhouse_rail_nav {
namespace {

void emitPose(YAML::Emitter& out, const char* key, const thorvald_base::Pose2D& pose) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "x" << YAML::Value << pose.x
      << YAML::Key << "y" << YAML::Value << pose.y << YAML::Key << "yaw" << YAML::Value << pose.yaw << YAML::EndMap;
}

void emitPoint(YAML::Emitter& out, const char* key, const Eigen::Vector2d& p) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << p.x() << p.y() << YAML::EndSeq;
}

bool readPose(const YAML::Node& node, const std::string& where, thorvald_base::Pose2D* pose, std::string* error) {
  try {
    *pose = thorvald_base::Pose2D(node["x"].as<double>(), node["y"].as<double>(), node["yaw"].as<double>());
  } catch (const YAML::Exception&) {
    *error = where + ": expected {x: m, y: m, yaw: rad}";
    return false;
  }
  if (!std::isfinite(pose->x) || !std::isfinite(pose->y) || !std::isfinite(pose->yaw)) {
    *error = where + ": not finite";
    return false;
  }
  return true;
}

bool readPoint(const YAML::Node& node, const std::string& where, Eigen::Vector2d* p, std::string* error) {
  try {
    const auto v = node.as<std::vector<double>>();
    if (v.size() == 2) {
      *p = {v[0], v[1]};
      return true;
    }
  } catch (const YAML::Exception&) {
  }
  *error = where + ": expected [x, y]";
  return false;
}

}  // namespace

bool saveRailSetFile(const RailSetFile& file, const std::string& path, std::string* error) {
  YAML::Emitter out;
  out.SetDoublePrecision(6);
  out << YAML::BeginMap;
  out << YAML::Key << "frame_id" << YAML::Value << file.frame_id;
  out << YAML::Key << "status" << YAML::Value << file.status;
  out << YAML::Key << "confidence" << YAML::Value << file.confidence;
  if (!file.reasons.empty()) out << YAML::Key << "reasons" << YAML::Value << file.reasons;
  out << YAML::Key << "headland_edge" << YAML::Value << YAML::BeginMap;
  emitPoint(out, "start", file.edge_start);
  emitPoint(out, "end", file.edge_end);
  emitPoint(out, "into_rows", file.into_rows);
  out << YAML::EndMap;
  out << YAML::Key << "rail_sets" << YAML::Value << YAML::BeginSeq;
  for (const auto& set : file.rail_sets) {
    out << YAML::BeginMap << YAML::Key << "index" << YAML::Value << set.index;
    out << YAML::Key << "status" << YAML::Value << (set.good ? "good" : "uncertain");
    if (!set.good) out << YAML::Key << "reason" << YAML::Value << set.reason;
    emitPose(out, "target_pose", set.target_pose);
    emitPose(out, "rail_frame", set.rail_frame);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  std::ofstream stream(path);
  if (!stream) {
    *error = "cannot write " + path;
    return false;
  }
  stream << "# Rail sets found by greenhouse_rail_nav/map_analyzer. Poses in frame_id: x, y [m], yaw [rad].\n"
         << "# target_pose is where the robot goes in front of each rail set; edit it if needed.\n"
         << "# A mission visits only the sets with status good; uncertain sets say why.\n"
         << out.c_str() << "\n";
  return static_cast<bool>(stream);
}

bool loadRailSetFile(const std::string& path, RailSetFile* file, std::string* error) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
  RailSetFile result;
  try {
    if (doc["frame_id"]) result.frame_id = doc["frame_id"].as<std::string>();
    if (doc["status"]) result.status = doc["status"].as<std::string>();
    if (doc["confidence"]) result.confidence = doc["confidence"].as<double>();
    if (doc["reasons"]) result.reasons = doc["reasons"].as<std::string>();
  } catch (const YAML::Exception&) {
    *error = path + ": frame_id, status and reasons must be strings, confidence a number";
    return false;
  }
  const YAML::Node edge = doc["headland_edge"];
  if (!edge || !readPoint(edge["start"], path + ": headland_edge.start", &result.edge_start, error) ||
      !readPoint(edge["end"], path + ": headland_edge.end", &result.edge_end, error) ||
      !readPoint(edge["into_rows"], path + ": headland_edge.into_rows", &result.into_rows, error)) {
    if (!edge) *error = path + ": missing headland_edge {start, end, into_rows}";
    return false;
  }
  const YAML::Node sets = doc["rail_sets"];
  if (!sets || !sets.IsSequence()) {
    *error = path + ": missing rail_sets (a list)";
    return false;
  }
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const std::string where = path + ": rail_sets[" + std::to_string(i) + "]";
    RailSetEstimate set;
    try {
      set.index = sets[i]["index"] ? sets[i]["index"].as<int>() : static_cast<int>(i);
      const std::string status = sets[i]["status"] ? sets[i]["status"].as<std::string>() : "good";
      if (status != "good" && status != "uncertain") {
        *error = where + ".status: expected good or uncertain, got '" + status + "'";
        return false;
      }
      set.good = status == "good";
      if (sets[i]["reason"]) set.reason = sets[i]["reason"].as<std::string>();
    } catch (const YAML::Exception&) {
      *error = where + ": index must be an integer, status and reason strings";
      return false;
    }
    if (!readPose(sets[i]["target_pose"], where + ".target_pose", &set.target_pose, error) ||
        !readPose(sets[i]["rail_frame"], where + ".rail_frame", &set.rail_frame, error)) {
      return false;
    }
    result.rail_sets.push_back(set);
  }
  *file = result;
  return true;
}

}  // namespace greenhouse_rail_nav
