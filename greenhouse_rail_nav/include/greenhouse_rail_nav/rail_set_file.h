#pragma once

#include <string>
#include <vector>

#include "greenhouse_rail_nav/map_analyzer.h"

namespace greenhouse_rail_nav {

/// What the mission reads on start-up: the rail sets in the map frame and the headland edge. The file is
/// YAML a person can edit (one entry per rail set, poses as {x, y, yaw}). Every set carries `status: good`
/// or `status: uncertain` with the reason; a mission visits only good sets (a set without a status, written
/// by hand, counts as good).
struct RailSetFile {
  std::string frame_id = "map";
  std::string status = "ok";  ///< the analysis' status: ok or uncertain
  double confidence = 1.0;    ///< the analysis' confidence [0, 1]
  std::string reasons;        ///< why the analysis is uncertain
  std::vector<RailSetEstimate> rail_sets;
  Eigen::Vector2d edge_start = Eigen::Vector2d::Zero();  ///< [m]
  Eigen::Vector2d edge_end = Eigen::Vector2d::Zero();    ///< [m]
  Eigen::Vector2d into_rows = Eigen::Vector2d::UnitY();  ///< unit vector
};

bool saveRailSetFile(const RailSetFile& file, const std::string& path, std::string* error);
/// Reads a file written by saveRailSetFile (or edited by hand); says which entry and key are wrong.
bool loadRailSetFile(const std::string& path, RailSetFile* file, std::string* error);

}  // namespace greenhouse_rail_nav
