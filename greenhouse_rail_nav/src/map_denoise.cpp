#include "greenhouse_rail_nav/map_denoise.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace greenhouse_rail_nav {

std::size_t removeSpeckle(thorvald_map::OccupancyGrid* map, double min_area_m2, double link_radius_m,
                          int occupied_value) {
  const std::size_t min_cells = std::max<std::size_t>(
      2, static_cast<std::size_t>(std::ceil(min_area_m2 / (map->resolution_m * map->resolution_m))));
  std::vector<bool> seen(map->data.size(), false);
  std::vector<std::size_t> component, stack;
  std::size_t cleared = 0;
  const auto w = static_cast<std::size_t>(map->width);
  // Neighbours: the 8 around a cell, or every cell within link_radius_m of it.
  const int reach = std::max(1, static_cast<int>(std::floor(link_radius_m / map->resolution_m + 1e-9)));
  const double reach2 = std::max(2.0, std::pow(link_radius_m / map->resolution_m, 2) + 1e-9);
  for (std::size_t start = 0; start < map->data.size(); ++start) {
    if (seen[start] || map->data[start] < occupied_value) continue;
    component.clear();
    stack.assign(1, start);
    seen[start] = true;
    // Depth-first flood fill; stops growing the list once the component is known to be large enough.
    bool large = false;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      if (!large) component.push_back(i);
      large = large || component.size() >= min_cells;
      const int c = static_cast<int>(i % w), r = static_cast<int>(i / w);
      for (int dr = -reach; dr <= reach; ++dr) {
        for (int dc = -reach; dc <= reach; ++dc) {
          if (dr * dr + dc * dc > reach2) continue;
          const int nc = c + dc, nr = r + dr;
          if (!map->inside(nc, nr)) continue;
          const std::size_t j = static_cast<std::size_t>(nr) * w + static_cast<std::size_t>(nc);
          if (seen[j] || map->data[j] < occupied_value) continue;
          seen[j] = true;
          stack.push_back(j);
        }
      }
    }
    if (large) continue;
    for (const std::size_t i : component) map->data[i] = thorvald_map::kFree;
    cleared += component.size();
  }
  return cleared;
}

}  // namespace greenhouse_rail_nav
