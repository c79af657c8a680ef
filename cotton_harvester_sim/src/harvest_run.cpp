#include "cotton_harvester_sim/harvest_run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <exception>
#include <memory>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/debug_overlay.h"

namespace cotton_harvester {
namespace sim {

namespace {

/// The scorer's view of one camera frame: which bolls were in view, how visible, and which detection was which
/// boll (the nearest true visible top within the tracker's match radius), in the tracker's row coordinates.
void scoreFrame(const RoverSim& sim, const perception::FrameResult& result, double rover_position_m,
                double y_forward_sign, double match_radius_m, HarvestRunReport* report) {
  std::vector<BollRecord>* records = &report->boll_records;
  if (result.end_effector) {
    const double top = sim.toCamera(sim.nozzlePosition()).z() - 0.5 * sim.params().geometry.effector_height_m;
    report->effector_depth_errors_m.push_back(result.end_effector->position.z - top);
  }
  const double radius = sim.params().row.boll_radius_m;
  const auto& bolls = sim.bolls();
  for (size_t i = 0; i < bolls.size(); ++i) {
    if (bolls[i].captured || !sim.bollInView(i)) continue;
    BollRecord& r = (*records)[i];
    ++r.frames_in_view;
    r.max_visible_fraction = std::max(r.max_visible_fraction, sim.bollVisibleFraction(i));
  }
  std::vector<bool> detected(bolls.size(), false);
  for (const auto& d : result.bolls) {
    const Eigen::Vector3d p(d.position.x, d.position.y, d.position.z);
    double best = match_radius_m;
    size_t best_i = bolls.size();
    for (size_t i = 0; i < bolls.size(); ++i) {
      if (bolls[i].captured) continue;
      const Eigen::Vector3d c = sim.toCamera(bolls[i].centre);
      const double dist = (p - (c - radius * c.normalized())).norm();
      if (dist < best) {
        best = dist;
        best_i = i;
      }
    }
    if (best_i == bolls.size() || detected[best_i]) continue;
    detected[best_i] = true;
    const Eigen::Vector3d c = sim.toCamera(bolls[best_i].centre);
    const Eigen::Vector3d top = c - radius * c.normalized();
    report->boll_depth_errors_m.push_back(p.z() - top.z());
    report->boll_errors_m.push_back(best);
    BollRecord& r = (*records)[best_i];
    ++r.frames_detected;
    if (d.reachable) ++r.frames_detected_reachable;
    r.sighted = true;
    r.along_row_m = rover_position_m + y_forward_sign * p.y();
    r.across_m = p.x();
    r.depth_m = p.z();
  }
}

}  // namespace

std::vector<bool> reachableBolls(const RoverSim& sim, double row_length_m) {
  const RoverGeometry& g = sim.params().geometry;
  const Eigen::Vector3d start_cam_world = sim.roverPosition();
  std::vector<bool> reachable;
  for (const BollTruth& b : sim.bolls()) {
    const Eigen::Vector3d c = sim.toCamera(b.centre);
    const double x_min = -g.arm_base_offset_m, x_max = -g.arm_base_offset_m + g.horizontal_travel_m;
    const double top_depth = c.z() - sim.params().row.boll_radius_m;
    const double along = b.centre.x() - start_cam_world.x() - g.camera_ahead_m;
    reachable.push_back(c.x() >= x_min && c.x() <= x_max && top_depth >= g.min_depth_m && top_depth <= g.max_depth_m &&
                        along <= row_length_m);
  }
  return reachable;
}

HarvestRunConfig pottedConfig(unsigned seed) {
  HarvestRunConfig c;
  c.sim.row.plants = 6;  // Table 2: six potted plants 30 cm apart, three bolls each, slope 0.2513 deg
  c.sim.row.plant_spacing_m = 0.30;
  c.sim.row.bolls_per_plant = 3;
  c.sim.row.slope_deg = 0.2513;
  c.sim.row.first_plant_x_m = 1.5;
  c.sim.row.seed = seed;
  c.sim.seed = seed;
  c.sim.start_x_m = -0.3;
  c.machine.row_length_m = 2.9;
  c.machine.bolls_present = 18;
  // A boll seen from further back and hidden from straight above: the rover moves (twice at most with the deadband
  // controller), the arm goes down, the pick is made: four frames without it.
  c.machine.remember_target_frames = 4;
  c.machine.tracker.order = control::TargetOrder::kAlongRow;
  c.machine.keep_target = true;
  c.machine.revisit_pending = true;
  // The arm of the simulated rover; leaves over a boll are swept aside before its pick.
  c.machine.actions = simActionParams(c.sim);
  c.machine.actions.clear_leaves_before_pick = true;
  c.time_limit_s = 900.0;
  return c;
}

HarvestRunConfig fieldConfig(unsigned seed) {
  HarvestRunConfig c = pottedConfig(seed);
  c.sim.row.plants = 17;  // Table 3: 5.3 m of undefoliated row on a 2.7668 deg slope
  c.sim.row.slope_deg = 2.7668;
  c.sim.row.leaves_per_plant = 12;  // undefoliated: more leaves, and one above 40 % of the bolls
  c.sim.row.leaf_over_boll_fraction = 0.4;
  c.machine.row_length_m = 6.4;
  c.machine.bolls_present = 17 * 3;
  c.machine.search_under_leaves = true;  // undefoliated: leaves hide bolls from every camera position on the row
  c.time_limit_s = 2400.0;
  return c;
}

void StateTimeTally::observe(const std::string& active_state, double now_s) {
  if (!active_state.empty()) report_->states_visited.insert(active_state);
  if (active_state == state_now_) return;
  if (!state_now_.empty()) report_->state_time_s[state_now_] += now_s - state_since_s_;
  if (!active_state.empty()) ++report_->state_entries[active_state];
  state_now_ = active_state;
  state_since_s_ = now_s;
}

void StateTimeTally::finish(double now_s) {
  if (!state_now_.empty()) report_->state_time_s[state_now_] += now_s - state_since_s_;
}

namespace {

/// The perception pipeline of the stack on the simulated rover: the colour detector, with partial bolls or without.
std::unique_ptr<perception::PerceptionPipeline> makePipeline(const HarvestRunConfig& config) {
  const perception::PerceptionParams pp = simPerceptionParams(config.sim);
  return std::make_unique<perception::PerceptionPipeline>(
      pp, std::make_unique<perception::ColourBollDetector>(config.partial_bolls ? simColourBollParams()
                                                                                : perception::ColourBollParams()));
}

/// The machine's last transition on stderr: simulated time, states, outcome, the rover, the points it decided on.
void printTransition(const thorvald_state_machine::StatusSnapshot& s, const control::HarvestMachine& machine,
                     const SimHarvestPlant& plant, const RoverSim& sim) {
  const auto& h = s.history.back();
  const auto points = machine.lastDecisionPoints();
  std::fprintf(stderr, "[%7.2f s] %s -> %s (%s) rover %.3f m", h.stamp_s, h.state.c_str(), h.next.c_str(),
               h.outcome.c_str(), plant.roverPositionM());
  if (points)
    std::fprintf(stderr, "  boll (%.3f %.3f %.3f) effector (%.3f %.3f %.3f)", points->first.x, points->first.y,
                 points->first.z, points->second.x, points->second.y, points->second.z);
  std::fprintf(stderr, "  captured %d\n", sim.bollsCaptured());
}

/// One record per boll with the truth known before the run: whether the arm can reach it along the driven stretch
/// and whether any camera position on the row could see it past the leaves as they grew (every 5 cm of the drive).
/// Returns the reachable flags.
std::vector<bool> startBollRecords(const RoverSim& sim, double row_length_m, HarvestRunReport* report) {
  const std::vector<bool> reachable = reachableBolls(sim, row_length_m);
  report->boll_records.resize(sim.bolls().size());
  for (size_t i = 0; i < reachable.size(); ++i) report->boll_records[i].reachable = reachable[i];
  std::vector<double> offsets;
  for (double s = 0.0; s <= row_length_m + 0.3; s += 0.05) offsets.push_back(s);
  for (size_t i = 0; i < reachable.size(); ++i)
    if (reachable[i]) report->boll_records[i].row_best_visible_fraction = sim.bestVisibleFractionAlongRow(i, offsets);
  return reachable;
}

/// The frame's images as the configuration asks: every frame into frames_dir, and the first one with the
/// end-effector and a boll as the debug image (`debug_written` set once it is written).
void writeFrameImages(const HarvestRunConfig& config, int frame, const cv::Mat& bgr,
                      const perception::FrameResult& result, bool* debug_written) {
  if (!config.frames_dir.empty()) {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%04d.png", frame);
    cv::imwrite(config.frames_dir + name, perception::drawDebugOverlay(bgr, result));
  }
  if (!*debug_written && result.end_effector && !result.bolls.empty()) {
    *debug_written = cv::imwrite(config.debug_image_path, perception::drawDebugOverlay(bgr, result));
  }
}

/// What the run did, after it: the machine's counts with the picks the simulation saw, the stack's frame and leaf
/// counts, the rover's travel and odometry error, and each boll's fate with the cause of a miss.
void fillReport(const RoverSim& sim, const SimHarvestPlant& plant, const control::HarvestMachine& machine,
                const control::HarvestParams& mp, double encoder_start_m, HarvestRunReport* report) {
  report->counts = machine.counts();
  report->machine_picked = report->counts.picked;
  report->counts.picked = sim.bollsCaptured();
  report->bolls_present = static_cast<int>(sim.bolls().size());
  report->counts.bolls_present = report->bolls_present;
  report->metrics = control::computeMetrics(report->counts);
  report->frames = plant.frames();
  report->frames_with_effector = plant.framesWithEffector();
  report->effector_rejected = plant.effectorRejected();
  report->effector_from_calibration = plant.effectorFromCalibration();
  report->picks_cleared = machine.actions().picksCleared();
  report->picks_redetected = machine.actions().picksRedetected();
  report->leaves_pushed = sim.leavesPushed();
  report->bolls_knocked_off = sim.bollsKnockedOff();
  report->leaf_searches = machine.actions().leafSearches();
  report->leaf_sweeps = machine.actions().leafSweeps();
  report->rover_track = plant.track();
  report->bolls = sim.bolls();
  report->rover_end = sim.roverPosition();
  const Eigen::Vector3d travel = report->rover_end - report->rover_start;
  report->odometry_error_m = (plant.roverPositionM() - encoder_start_m) - std::copysign(travel.norm(), travel.x());
  report->divergences = sim.divergences();
  const std::vector<control::TrackedBoll> tracks = machine.tracks();
  for (size_t i = 0; i < report->bolls.size(); ++i) {
    BollRecord& r = report->boll_records[i];
    r.captured = report->bolls[i].captured;
    r.closest_vacuum_m = report->bolls[i].closest_vacuum_m;
    const MissCause cause = classifyMiss(r, tracks, mp.tracker);
    report->miss_causes.push_back(cause);
    report->misses.add(cause);
  }
}

/// Builds the rover and its stack, runs the machine to its end and fills the report; throws what they throw.
void harvest(const HarvestRunConfig& config, HarvestRunReport* report) {
  RoverSim sim(config.sim);
  auto pipeline = makePipeline(config);
  StackParams stack = simStackParams(config.sim);
  stack.effector_search_near_arm = config.effector_search_near_arm;
  SimHarvestPlant plant(sim, stack, config.machine.actions.arm, std::move(pipeline));
  control::HarvestParams mp = config.machine;
  mp.bolls_present = static_cast<int>(sim.bolls().size());
  if (auto bad = mp.check(); !bad.empty()) throw std::invalid_argument("harvest machine: " + bad);
  control::HarvestMachine machine(plant, mp);
  StateTimeTally tally(report);
  std::uint32_t printed = 0;
  machine.machine().setObserver([&](const thorvald_state_machine::StatusSnapshot& s) {
    tally.observe(s.active_state, sim.time());
    if (config.status_observer) config.status_observer(s);
    if (config.verbose && s.transitions != printed && !s.history.empty()) {
      printed = s.transitions;
      printTransition(s, machine, plant, sim);
    }
  });
  machine.machine().setClock([&sim] { return sim.time(); });
  bool debug_written = config.debug_image_path.empty();
  const double t0 = sim.time();
  const std::vector<bool> reachable = startBollRecords(sim, mp.row_length_m, report);
  plant.setFrameHook([&](const cv::Mat& bgr, const perception::FrameResult& result) {
    if (sim.time() - t0 > config.time_limit_s) machine.machine().requestPreempt();
    scoreFrame(sim, result, plant.roverPositionM(), mp.decision.y_forward_sign, mp.tracker.match_radius_m, report);
    writeFrameImages(config, plant.frames(), bgr, result, &debug_written);
  });
  report->rover_start = sim.roverPosition();
  const double encoder_start_m = plant.roverPositionM();
  report->bolls_reachable = static_cast<int>(std::count(reachable.begin(), reachable.end(), true));
  report->outcome = machine.run();
  tally.finish(sim.time());
  report->sim_time_s = sim.time() - t0;
  fillReport(sim, plant, machine, mp, encoder_start_m, report);
}

}  // namespace

HarvestRunReport runHarvest(const HarvestRunConfig& config) {
  HarvestRunReport report;
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    harvest(config, &report);
  } catch (const std::exception& e) {
    report.error = e.what();
  }
  report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return report;
}

bool writePathPng(const HarvestRunReport& report, const std::string& path) {
  if (report.bolls.empty()) return false;
  // Top view: x along the row (right), y across (up); 200 px per metre.
  double x_min = report.rover_start.x(), x_max = report.rover_end.x();
  for (const auto& b : report.bolls) {
    x_min = std::min(x_min, b.centre.x());
    x_max = std::max(x_max, b.centre.x());
  }
  x_min -= 0.5;
  x_max += 0.5;
  const double scale = 200.0, y_half = 0.8;
  const int w = static_cast<int>((x_max - x_min) * scale), h = static_cast<int>(2 * y_half * scale) + 40;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(60, 80, 110));
  auto px = [&](double x, double y) {
    return cv::Point(static_cast<int>((x - x_min) * scale), static_cast<int>((y_half - y) * scale) + 40);
  };
  // The camera's path along the row (the encoder's positions from the start).
  const double cam_x0 = report.rover_start.x() + RoverGeometry().camera_ahead_m;
  for (size_t i = 1; i < report.rover_track.size(); ++i) {
    cv::line(img, px(cam_x0 + report.rover_track[i - 1].second, 0.0), px(cam_x0 + report.rover_track[i].second, 0.0),
             cv::Scalar(255, 200, 0), 2);
  }
  for (const auto& b : report.bolls) {
    cv::circle(img, px(b.centre.x(), b.centre.y()), 7, b.captured ? cv::Scalar(0, 200, 0) : cv::Scalar(0, 0, 230),
               b.captured ? -1 : 2);
  }
  cv::putText(img, "camera path (blue), picked (filled green), missed (red)", cv::Point(5, 20),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1);
  return cv::imwrite(path, img);
}

}  // namespace sim
}  // namespace cotton_harvester
