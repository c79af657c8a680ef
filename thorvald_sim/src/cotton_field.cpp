// A field of cotton rows (makeCottonFieldWorld) and its rows' end waypoints.
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>

#include "thorvald_sim/cotton_world.h"
#include "world_checks.h"

namespace thorvald_sim {

using detail::requirePositive;

namespace {

/// Renames a row's plants to the field's numbering and its soil parts to the row's, and drops its ground plane
/// (the first row's is the field's).
std::string fieldRowXml(const std::string& row_xml, int row, int plant_offset, bool keep_ground, bool collide) {
  static const std::regex kPlant("\"plant([0-9]+)_");
  std::string out;
  std::istringstream lines(row_xml);
  for (std::string line; std::getline(lines, line);) {
    if (!keep_ground && line.rfind("<geom name=\"ground\"", 0) == 0) continue;
    std::string renamed;
    auto end = std::sregex_iterator();
    std::size_t last = 0;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), kPlant); it != end; ++it) {
      renamed += line.substr(last, it->position() - last);
      renamed += "\"plant" + std::to_string(std::stoi((*it)[1]) + plant_offset) + "_";
      last = it->position() + it->length();
    }
    renamed += line.substr(last);
    for (const char* part : {"name=\"clod", "name=\"weed"}) {
      const std::size_t at = renamed.find(part);
      if (at != std::string::npos) renamed.insert(at + 6, "row" + std::to_string(row) + "_");
    }
    if (!collide && renamed.rfind("<geom name=\"plant", 0) == 0 && renamed.find("contype=") == std::string::npos)
      renamed.insert(5, " contype=\"0\" conaffinity=\"0\"");
    out += renamed + "\n";
  }
  return out;
}

}  // namespace

WorldDescription makeCottonFieldWorld(const CottonFieldParams& p, CottonFieldTruth* truth) {
  if (p.rows < 1 || p.rows > 200) throw std::invalid_argument("rows must be within 1..200");
  requirePositive(p.row_spacing_m, "row_spacing");
  requirePositive(p.row_length_m, "row_length");
  requirePositive(p.row.plant_spacing_m, "plant_spacing");
  CottonFieldTruth t;
  std::string xml;
  const int plants = 1 + static_cast<int>(std::floor(p.row_length_m / p.row.plant_spacing_m + 1e-9));
  for (int k = 0; k < p.rows; ++k) {
    CottonRowParams row = p.row;
    row.plants = plants;
    row.row_y_m = p.row.row_y_m + k * p.row_spacing_m;
    row.seed = p.row.seed + static_cast<unsigned>(k);
    CottonRowTruth rt;
    const WorldDescription w = makeCottonRowWorld(row, &rt);
    const int offset = static_cast<int>(t.plants.plant_bases.size());
    xml += fieldRowXml(w.worldbody, k, offset, k == 0, p.plants_collide);
    t.plants.plant_bases.insert(t.plants.plant_bases.end(), rt.plant_bases.begin(), rt.plant_bases.end());
    t.plants.bolls.insert(t.plants.bolls.end(), rt.bolls.begin(), rt.bolls.end());
    for (int b : rt.boll_plant) t.plants.boll_plant.push_back(b + offset);
    t.plants.boll_half_open.insert(t.plants.boll_half_open.end(), rt.boll_half_open.begin(), rt.boll_half_open.end());
    t.plant_row.insert(t.plant_row.end(), rt.plant_bases.size(), k);
    t.row_start.emplace_back(rt.plant_bases.front().x(), rt.plant_bases.front().y());
    t.row_end.emplace_back(rt.plant_bases.back().x(), rt.plant_bases.back().y());
  }
  t.plants.params = p.row;
  t.plants.params.plants = static_cast<int>(t.plants.plant_bases.size());
  if (truth) *truth = t;
  return {"cotton_field", xml, 0.0};
}

bool writeCottonFieldWaypoints(const CottonFieldTruth& t, const std::string& path) {
  std::ofstream out(path);
  if (!out) return false;
  out.precision(9);
  out << "# The rows' ends of a cotton field (world frame, metres), as recorded with the GNSS at each row's first and\n"
      << "# last plant. Written by thorvald_sim's cotton field generator.\nrows:\n";
  for (std::size_t k = 0; k < t.row_start.size(); ++k)
    out << "  - {row: " << k << ", start: [" << t.row_start[k].x() << ", " << t.row_start[k].y() << "], end: ["
        << t.row_end[k].x() << ", " << t.row_end[k].y() << "]}\n";
  return static_cast<bool>(out);
}

}  // namespace thorvald_sim
