// Who is a person near the UV robot (obstacle_zones.h), on scans drawn through thorvald_sim's lidar profiles:
// `ideal` (1 cm range noise) and `datasheet` (the UTM-30LX model: noise, mixed pixels at edges, glancing losses,
// dropouts). Person-sized round bodies at 0.5-6 m must always be found; trolleys' faces and corners, crates, a wall's
// end, pipe ends and a ventilation line's top must not be taken for people within 3 m of the robot. Seeds 1000-1019,
// not those the classification was tuned on. Prints the table of person recall and phantom rate per scan. Then the
// recorded datasheet scans of two phantoms of the former zone (test/data/zone_scans_datasheet.txt) through the whole
// zone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "greenhouse_rail_nav/obstacle_zones.h"
#include "thorvald_sim/lidar_model.h"

namespace grn = greenhouse_rail_nav;

namespace {

constexpr double kLidarX = 0.45;
constexpr int kBeams = 1081;
constexpr double kAngleMin = -2.356, kAngleStep = 4.712 / 1080.0;

struct Circle {
  double x, y, r;
};
struct Segment {
  double ax, ay, bx, by;
};

/// A scene in the lidar's plane (base_link): round bodies and straight faces.
struct Scene {
  std::vector<Circle> circles;
  std::vector<Segment> segments;

  void box(double cx, double cy, double half_x, double half_y, double yaw) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    const double corner[4][2] = {{-half_x, -half_y}, {half_x, -half_y}, {half_x, half_y}, {-half_x, half_y}};
    for (int i = 0; i < 4; ++i) {
      const double* a = corner[i];
      const double* b = corner[(i + 1) % 4];
      segments.push_back(
          {cx + c * a[0] - s * a[1], cy + s * a[0] + c * a[1], cx + c * b[0] - s * b[1], cy + s * b[0] + c * b[1]});
    }
  }

  /// The true range and incidence of every beam of the lidar at (kLidarX, 0).
  std::vector<thorvald_sim::LidarBeam> cast() const {
    std::vector<thorvald_sim::LidarBeam> beams(kBeams);
    for (int i = 0; i < kBeams; ++i) {
      const double a = kAngleMin + i * kAngleStep, c = std::cos(a), s = std::sin(a);
      double best = 1e9, nx = 0.0, ny = 0.0;
      for (const Circle& k : circles) {
        const double dx = k.x - kLidarX, dy = k.y, along = dx * c + dy * s;
        const double h2 = k.r * k.r - (dx * dx + dy * dy - along * along);
        const double t = h2 >= 0.0 ? along - std::sqrt(h2) : -1.0;
        if (t > 0.05 && t < best) best = t, nx = (kLidarX + t * c - k.x) / k.r, ny = (t * s - k.y) / k.r;
      }
      for (const Segment& g : segments) {
        const double ex = g.bx - g.ax, ey = g.by - g.ay, den = c * ey - s * ex;
        if (std::fabs(den) < 1e-12) continue;
        const double t = ((g.ax - kLidarX) * ey - g.ay * ex) / den, u = ((g.ax - kLidarX) * s - g.ay * c) / den;
        if (t > 0.05 && u >= 0.0 && u <= 1.0 && t < best) {
          const double len = std::hypot(ex, ey);
          best = t, nx = -ey / len, ny = ex / len;
        }
      }
      if (best < 1e8) beams[i] = {best, std::acos(std::min(1.0, std::fabs(nx * c + ny * s)))};
    }
    return beams;
  }
};

/// One scan of `scene` in base_link, scan order, through the profile's model.
std::vector<grn::ScanPoint> scan(const Scene& scene, bool datasheet, unsigned seed) {
  std::mt19937 rng(seed);
  const std::vector<thorvald_sim::LidarBeam> beams = scene.cast();
  std::vector<float> ranges(beams.size(), INFINITY);
  if (datasheet) {
    ranges = thorvald_sim::applyLidarModel(beams, 0.1, 30.0, thorvald_sim::LidarModel(), rng);
  } else {  // the ideal lidar: the true range with the sensor file's 1 cm of Gaussian noise
    std::normal_distribution<double> noise(0.0, 0.01);
    for (size_t i = 0; i < beams.size(); ++i)
      if (beams[i].range_m >= 0.1 && beams[i].range_m <= 30.0) ranges[i] = beams[i].range_m + noise(rng);
  }
  std::vector<grn::ScanPoint> pts;
  for (size_t i = 0; i < ranges.size(); ++i) {
    if (!std::isfinite(ranges[i])) continue;
    const double a = kAngleMin + i * kAngleStep;
    pts.push_back({kLidarX + ranges[i] * std::cos(a), ranges[i] * std::sin(a)});
  }
  return pts;
}

/// Phantoms count within this of base_link (twice the headland radius: the zone near the robot) [m].
constexpr double kPhantomRange = 3.0;

/// Person clusters of one scan: (found near (x, y), phantoms: others within kPhantomRange).
std::pair<bool, int> people(const std::vector<grn::ScanPoint>& pts, double x, double y, bool want) {
  const grn::ZoneParams p;
  bool found = false;
  int others = 0;
  for (const grn::PointCluster& c : grn::clusterScan(pts, p, kLidarX)) {
    if (!c.person) continue;
    if (want && std::hypot(c.x - x, c.y - y) < 0.4) {
      found = true;
    } else if (std::hypot(c.x, c.y) < kPhantomRange) {
      ++others;
    }
  }
  return {found, others};
}

/// The room around every scene: a far wall and a side wall, as in a greenhouse's headland.
Scene room() {
  Scene s;
  s.segments.push_back({8.0, -6.0, 8.0, 6.0});
  s.segments.push_back({-6.0, 4.0, 8.0, 4.0});
  return s;
}

/// The scenes that hold no person, each with several poses.
std::vector<std::pair<std::string, std::vector<Scene>>> phantomScenes() {
  std::vector<std::pair<std::string, std::vector<Scene>>> out;
  std::vector<Scene> trolley, crate, wall_end, pipes, vent;
  for (int k = 0; k < 7; ++k) {
    const double yaw = k * M_PI / 12.0;
    for (double d : {1.2, 2.0, 3.0}) {
      Scene s = room();
      s.box(kLidarX + d, 0.4, 0.3, 0.5, yaw);  // a trolley 0.6 x 1.0 m
      trolley.push_back(s);
      s = room();
      s.box(kLidarX + d, -0.3, 0.2, 0.2, yaw);  // a crate 0.4 m square
      crate.push_back(s);
    }
    Scene s = room();  // the end of a 0.2 m thick partition wall, seen from the side and the front
    s.box(kLidarX + 1.0 + 0.3 * k, 1.5, 1.0, 0.1, 0.0);
    wall_end.push_back(s);
    s = room();  // heating pipes' ends (0.051 m) at the headland edge, both of a set and the next
    for (double y0 : {-0.8, 0.8})
      for (double dy : {-0.275, 0.275}) s.circles.push_back({kLidarX + 0.6 + 0.2 * k, y0 + dy, 0.0255});
    pipes.push_back(s);
    // A ventilation line (0.3 m, its top 2 cm below the lidar's plane) beside the robot, its end ahead or behind:
    // the plane of a pitching robot cuts its top in a strip 0.1 m wide with a round end.
    s = room();
    const double end_x = kLidarX - 0.5 + 0.3 * k;
    s.circles.push_back({end_x, 0.8, 0.05});
    s.segments.push_back({end_x - 6.0, 0.75, end_x, 0.75});
    s.segments.push_back({end_x - 6.0, 0.85, end_x, 0.85});
    vent.push_back(s);
  }
  out.emplace_back("trolley (faces, corners) at 1.2-3 m", trolley);
  out.emplace_back("crate 0.4 m at 1.2-3 m", crate);
  out.emplace_back("a partition wall's end", wall_end);
  out.emplace_back("heating pipes' ends", pipes);
  out.emplace_back("ventilation line's top and end", vent);
  return out;
}

constexpr unsigned kSeed0 = 1000, kSeeds = 20;

}  // namespace

TEST(ZoneClassification, PeopleAreFoundAndNothingElseIsAPersonInBothProfiles) {
  std::printf("%-40s %-10s %8s %8s %8s\n", "scene", "profile", "scans", "recall", "phantom");
  for (bool datasheet : {false, true}) {
    const char* profile = datasheet ? "datasheet" : "ideal";
    for (double r : {0.2, 0.25, 0.3}) {
      int scans = 0, found = 0, phantoms = 0;
      for (double d : {0.5, 1.0, 2.0, 4.0, 6.0}) {
        for (double bearing : {0.0, 0.6, -1.2}) {
          for (unsigned seed = kSeed0; seed < kSeed0 + kSeeds; ++seed) {
            Scene s = room();
            const double x = kLidarX + (d + r) * std::cos(bearing), y = (d + r) * std::sin(bearing);
            s.circles.push_back({x, y, r});
            const auto [hit, others] = people(scan(s, datasheet, seed), x, y, true);
            ++scans, found += hit, phantoms += others;
            EXPECT_TRUE(hit) << profile << ": a person of radius " << r << " m at " << d << " m, bearing " << bearing
                             << ", seed " << seed << " was missed";
          }
        }
      }
      std::ostringstream name;
      name << "person r " << r << " m at 0.5-6 m";
      std::printf("%-40s %-10s %8d %7.1f%% %7.2f%%\n", name.str().c_str(), profile, scans, 100.0 * found / scans,
                  100.0 * phantoms / scans);
      EXPECT_EQ(phantoms, 0);
    }
    for (const auto& [name, scenes] : phantomScenes()) {
      int scans = 0, phantoms = 0;
      for (const Scene& s : scenes) {
        for (unsigned seed = kSeed0; seed < kSeed0 + kSeeds; ++seed) {
          ++scans;
          phantoms += people(scan(s, datasheet, seed), 0.0, 0.0, false).second > 0;
        }
      }
      std::printf("%-40s %-10s %8d %8s %7.2f%%\n", name.c_str(), profile, scans, "-", 100.0 * phantoms / scans);
      // A strip at the lidar's height ending round is person-like from some poses, scan after scan; on the robot the
      // plane meets the ventilation line's top only while pitching, for a scan or two (RecordedDatasheetPhantoms...).
      if (name.rfind("ventilation", 0) == 0)
        EXPECT_LT(phantoms, scans / 5) << profile << ": " << name;
      else
        EXPECT_EQ(phantoms, 0) << profile << ": " << name;
    }
  }
}

namespace {

struct RecordedScan {
  std::string what;
  double lidar_x = 0.0;
  std::vector<grn::ScanPoint> points;
  std::set<std::pair<double, double>> known;
};

std::vector<RecordedScan> recordedScans() {
  std::ifstream f(std::string(TEST_DATA_DIR) + "/zone_scans_datasheet.txt");
  std::vector<RecordedScan> out;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    if (line.rfind("scan", 0) == 0) {
      std::string tag;
      double t = 0.0;
      int n = 0;
      out.emplace_back();
      in >> tag >> out.back().what >> t >> out.back().lidar_x >> n;
      continue;
    }
    grn::ScanPoint q;
    int known = 0;
    in >> q.x >> q.y >> known;
    out.back().points.push_back(q);
    if (known) out.back().known.insert({q.x, q.y});
  }
  return out;
}

}  // namespace

TEST(ZoneClassification, RecordedDatasheetPhantomsHoldNobody) {
  const std::vector<RecordedScan> scans = recordedScans();
  ASSERT_EQ(scans.size(), 10u);
  const grn::ZoneParams p;
  grn::PersonConfirmation confirm(p);
  grn::ZoneContext ctx;
  ctx.phase = grn::ZonePhase::kHeadland;
  int single_scan_people = 0;
  for (const RecordedScan& s : scans) {
    const grn::KnownPoint known = [&s](double x, double y) { return s.known.count({x, y}) > 0; };
    grn::ZoneVerdict v = grn::evaluateZone(s.points, s.lidar_x, ctx, p, known);
    single_scan_people += v.person;
    confirm.apply(ctx.phase, &v);
    EXPECT_FALSE(v.blocked) << s.what << ": " << v.why;
  }
  // The ventilation line's top, sliced by the lidar's plane as the robot pitches, looks round in one scan of five:
  // the confirmation over consecutive scans is what keeps the robot going.
  EXPECT_LE(single_scan_people, 1);
}

TEST(ZoneClassification, APersonIsConfirmedOnTheThirdScanAndARowObstacleAtOnce) {
  grn::ZoneParams p;
  grn::PersonConfirmation confirm(p);
  Scene s = room();
  s.circles.push_back({kLidarX + 1.0, 0.3, 0.25});
  grn::ZoneContext ctx;
  ctx.phase = grn::ZonePhase::kHeadland;
  for (unsigned k = 0; k < 3; ++k) {
    grn::ZoneVerdict v = grn::evaluateZone(scan(s, true, kSeed0 + k), kLidarX, ctx, p);
    ASSERT_TRUE(v.person);
    confirm.apply(ctx.phase, &v);
    EXPECT_EQ(v.blocked, k == 2) << "scan " << k;
    EXPECT_EQ(v.why.find("a person near the robot") == 0, k == 2) << v.why;
  }
  // In the row anything short of the end blocks at once.
  ctx.phase = grn::ZonePhase::kRow;
  ctx.row_end_m = 10.0;
  grn::PersonConfirmation row_confirm(p);
  grn::ZoneVerdict v = grn::evaluateZone(scan(s, true, kSeed0), kLidarX, ctx, p);
  row_confirm.apply(ctx.phase, &v);
  EXPECT_TRUE(v.blocked);
  // Reversing, the rear range finders block at once whatever the lidar sees.
  ctx.phase = grn::ZonePhase::kReverse;
  grn::PersonConfirmation rear_confirm(p);
  v = grn::evaluateZone({}, kLidarX, ctx, p, {}, {0.5});
  rear_confirm.apply(ctx.phase, &v);
  EXPECT_TRUE(v.blocked);
  EXPECT_NE(v.why.find("behind"), std::string::npos);
}
