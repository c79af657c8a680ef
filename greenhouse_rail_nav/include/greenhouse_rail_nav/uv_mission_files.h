#pragma once

#include <set>
#include <string>
#include <vector>

#include "greenhouse_rail_nav/rail_set_file.h"
#include "greenhouse_rail_nav/uv_mission.h"

namespace greenhouse_rail_nav {

// What the UV mission reads and writes besides its topics: its targets from the rail-set file, the progress file
// that lets a restarted mission skip the sets already treated, and the report of a run.

/// The mission's targets from map_analyzer's rail-set file, in the file's order: every set with its target pose,
/// its verdict (uncertain sets are kept, to be reported as skipped) and the analyzer's reason.
std::vector<MissionTarget> missionTargets(const RailSetFile& file);

/// Sets each target's rail length: a rail set's `length` [m] in the rail-set file at `path` (a person measured it, or
/// a tool wrote it: the map of the headland does not show it), else `fallback_m` (0: unknown). Throws
/// YAML::Exception on a file that is not YAML or a `length` that is not a number.
void setRailLengths(const std::string& path, double fallback_m, std::vector<MissionTarget>* targets);

/// The rail sets an earlier run treated, from the progress file at `path` (YAML, `treated: [0, 2, ...]`). Empty
/// when `path` is empty, the file does not exist or has no `treated` list; throws YAML::Exception on a file that
/// is not YAML or holds something other than integers there.
std::set<int> loadProgress(const std::string& path);

/// Writes the progress file (a comment saying what it is, then `treated: [...]`); nothing when `path` is empty.
void saveProgress(const std::string& path, const std::set<int>& done);

/// The report of one run as CSV (a header line, then one line per rail set the run tried), as the node publishes it
/// on mission/report.
std::string reportCsv(const std::vector<RailSetReport>& reports);

}  // namespace greenhouse_rail_nav
