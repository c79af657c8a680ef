#include "greenhouse_rail_nav/cell_clustering.h"

#include <cmath>
#include <numeric>
#include <unordered_map>

namespace greenhouse_rail_nav {
namespace {

/// Union-find over cell indices with path halving.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace

std::vector<CellCluster> clusterOccupiedCells(const thorvald_map::OccupancyGrid& map, double link_radius_m,
                                              std::size_t min_cells, int occupied_value) {
  // Index of each occupied cell in a compact list (-1 elsewhere).
  std::vector<int> index(map.data.size(), -1);
  std::vector<std::pair<int, int>> occupied;
  for (int r = 0; r < map.height; ++r) {
    for (int c = 0; c < map.width; ++c) {
      if (map.at(c, r) >= occupied_value) {
        index[static_cast<std::size_t>(r) * map.width + c] = static_cast<int>(occupied.size());
        occupied.emplace_back(c, r);
      }
    }
  }
  // Neighbour offsets within the link radius; only the "forward" half so each pair is visited once.
  const int reach = std::max(1, static_cast<int>(std::floor(link_radius_m / map.resolution_m + 1e-9)));
  std::vector<std::pair<int, int>> offsets;
  for (int dr = 0; dr <= reach; ++dr) {
    for (int dc = -reach; dc <= reach; ++dc) {
      if (dr == 0 && dc <= 0) continue;
      if (dr * dr + dc * dc <= reach * reach) offsets.emplace_back(dc, dr);
    }
  }
  DisjointSets sets(occupied.size());
  for (std::size_t i = 0; i < occupied.size(); ++i) {
    const auto [c, r] = occupied[i];
    for (const auto& [dc, dr] : offsets) {
      const int nc = c + dc, nr = r + dr;
      if (!map.inside(nc, nr)) continue;
      const int j = index[static_cast<std::size_t>(nr) * map.width + nc];
      if (j >= 0) sets.join(i, static_cast<std::size_t>(j));
    }
  }
  std::unordered_map<std::size_t, std::size_t> cluster_of_root;
  std::vector<CellCluster> clusters;
  for (std::size_t i = 0; i < occupied.size(); ++i) {
    const std::size_t root = sets.find(i);
    auto it = cluster_of_root.find(root);
    if (it == cluster_of_root.end()) {
      it = cluster_of_root.emplace(root, clusters.size()).first;
      clusters.emplace_back();
    }
    clusters[it->second].points.push_back(map.cellCentre(occupied[i].first, occupied[i].second));
  }
  std::vector<CellCluster> kept;
  for (auto& cluster : clusters) {
    if (cluster.points.size() >= min_cells) kept.push_back(std::move(cluster));
  }
  return kept;
}

}  // namespace greenhouse_rail_nav
