#pragma once

#include <string>

#include "greenhouse_rail_nav/map_analyzer.h"
#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// Writes a PNG of the map (north up) with what the analysis found drawn over it: rear wall (blue), rows
/// (green), side walls (dark cyan), headland edge (red), keep-out line at keep_out_margin_m beyond it
/// (magenta, dashed), rail frames as arrows along the rails (green: good, orange: uncertain) and target
/// poses as circles with a heading tick. Small maps are scaled up to at least ~800 px; maps larger than
/// max_pixels on a side are shrunk. Returns false with the reason in *error.
bool writeMapOverlayPng(const thorvald_map::OccupancyGrid& map, const MapAnalysis& analysis, const std::string& path,
                        std::string* error, double keep_out_margin_m = 0.0, int max_pixels = 6000);

}  // namespace greenhouse_rail_nav
