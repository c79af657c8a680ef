#include "greenhouse_rail_nav/uv_mission_files.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

namespace greenhouse_rail_nav {

std::vector<MissionTarget> missionTargets(const RailSetFile& file) {
  std::vector<MissionTarget> targets;
  for (const auto& s : file.rail_sets) targets.push_back({s.index, s.target_pose, s.good, s.reason});
  return targets;
}

void setRailLengths(const std::string& path, double fallback_m, std::vector<MissionTarget>* targets) {
  for (MissionTarget& t : *targets) t.rail_length_m = fallback_m;
  const YAML::Node sets = YAML::LoadFile(path)["rail_sets"];
  if (!sets || !sets.IsSequence()) return;
  for (const auto& s : sets) {
    if (!s["index"] || !s["length"]) continue;
    const int index = s["index"].as<int>();
    for (MissionTarget& t : *targets)
      if (t.index == index) t.rail_length_m = s["length"].as<double>();
  }
}

std::set<int> loadProgress(const std::string& path) {
  std::set<int> done;
  if (path.empty()) return done;
  std::ifstream in(path);
  if (!in) return done;
  const YAML::Node n = YAML::Load(in);
  if (n["treated"] && n["treated"].IsSequence())
    for (const auto& v : n["treated"]) done.insert(v.as<int>());
  return done;
}

void saveProgress(const std::string& path, const std::set<int>& done) {
  if (path.empty()) return;
  std::ofstream out(path);
  out << "# Rail sets the UV mission has treated; a restarted mission skips them. Delete to start over.\ntreated: [";
  bool first = true;
  for (int i : done) {
    out << (first ? "" : ", ") << i;
    first = false;
  }
  out << "]\n";
}

std::string reportCsv(const std::vector<RailSetReport>& reports) {
  std::ostringstream o;
  o << "rail_set,treated,result,align_attempts,entry_attempts,searches,rail_length_m,lights_on_s,speed_mean_mps,"
       "speed_std_mps,duration_s,lit_pct,pauses\n";
  for (const auto& r : reports)
    o << r.index << "," << (r.treated ? 1 : 0) << ",\"" << r.result << "\"," << r.align_attempts << ","
      << r.entry_attempts << "," << r.searches << "," << r.rail_length_m << "," << r.lights_on_s << ","
      << r.speed_mean_mps << "," << r.speed_std_mps << "," << r.duration_s << "," << r.lit_pct << "," << r.pauses
      << "\n";
  return o.str();
}

}  // namespace greenhouse_rail_nav
