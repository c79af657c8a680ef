// map_analyzer: finds the rail sets in a headland map (paper §V-B) and publishes target poses, the
// headland edge, the keep-out grid (virtual wall) and markers. Thin shell around analyzeMap().
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PolygonStamped.h>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <thorvald_common/ros/param_reader.h>

#include "greenhouse_rail_nav/keep_out_grid.h"
#include "greenhouse_rail_nav/map_analyzer.h"
#include "thorvald_map/map_file.h"
#include "greenhouse_rail_nav/map_overlay.h"
#include "greenhouse_rail_nav/rail_set_file.h"
#include "map_messages.h"
#include "thorvald_map/ros/conversions.h"

namespace greenhouse_rail_nav {
namespace {

struct NodeSettings {
  std::string map_file;     // empty: take the map from the `map` topic
  std::string output_file;  // empty: write no file
  std::string frame_id = "map";
  std::string overlay_png;  // empty: no picture
  int max_map_cells = 200000000;
  MapAnalyzerParams analysis;
};

/// Reads and checks every private parameter; throws thorvald_common::ParamError naming the bad one.
NodeSettings loadSettings(const ros::NodeHandle& pnh) {
  using thorvald_common::ParamRange;
  thorvald_common::ParamReader r(pnh);
  NodeSettings s;
  const ParamRange positive = ParamRange::above(0.0);
  const ParamRange any = ParamRange::any();
  s.map_file = r.text("map_file", s.map_file);
  s.output_file = r.text("output_file", s.output_file);
  s.frame_id = r.text("frame_id", s.frame_id);
  s.overlay_png = r.text("overlay_png", s.overlay_png);
  s.max_map_cells = r.integer("max_map_cells", s.max_map_cells, 1);
  auto& a = s.analysis;
  a.rail_set_spacing_m = r.number("rail_set_spacing_m", a.rail_set_spacing_m, ParamRange::aboveUpTo(0.0, 20.0), "m");
  a.rail_gauge_m = r.number("rail_gauge_m", a.rail_gauge_m, ParamRange::aboveUpTo(0.0, 3.0), "m");
  a.target_in_rail.x = r.number("target_x_m", a.target_in_rail.x, ParamRange::closed(-20.0, 20.0), "m");
  a.target_in_rail.y = r.number("target_y_m", a.target_in_rail.y, ParamRange::closed(-20.0, 20.0), "m");
  a.target_in_rail.yaw = r.number("target_yaw_rad", a.target_in_rail.yaw, ParamRange::closed(-M_PI, M_PI), "rad");
  a.cluster_link_radius_m = r.number("cluster_link_radius_m", a.cluster_link_radius_m, positive, "m");
  a.min_cluster_cells = r.integer("min_cluster_cells", a.min_cluster_cells, 2);
  a.lines.min_linearity = r.number("min_linearity", a.lines.min_linearity, ParamRange{0.0, 1.0, true, true});
  a.lines.min_length_m = r.number("min_line_length_m", a.lines.min_length_m, positive, "m");
  a.lines.split_inlier_m = r.number("split_inlier_m", a.lines.split_inlier_m, positive, "m");
  a.lines.max_gap_m = r.number("max_gap_m", a.lines.max_gap_m, positive, "m");
  a.lines.merge_angle_rad = r.number("merge_angle_rad", a.lines.merge_angle_rad, positive, "rad");
  a.lines.merge_offset_m = r.number("merge_offset_m", a.lines.merge_offset_m, positive, "m");
  a.perpendicular_tolerance_rad = r.number("perpendicular_tolerance_rad", a.perpendicular_tolerance_rad,
                                           ParamRange{0.0, M_PI / 4, true, true}, "rad");
  a.min_headland_depth_m = r.number("min_headland_depth_m", a.min_headland_depth_m, ParamRange::atLeast(0.0), "m");
  a.edge_tolerance_m = r.number("edge_tolerance_m", a.edge_tolerance_m, positive, "m");
  a.spacing_tolerance = r.number("spacing_tolerance", a.spacing_tolerance, ParamRange{0.0, 0.5, true, true});
  a.keep_out_margin_m = r.number("keep_out_margin_m", a.keep_out_margin_m, any, "m");
  a.speckle_max_area_m2 = r.number("speckle_max_area_m2", a.speckle_max_area_m2, ParamRange::closed(0.0, 0.1), "m^2");
  a.speckle_link_radius_m =
      r.number("speckle_link_radius_m", a.speckle_link_radius_m, ParamRange::closed(0.0, 0.5), "m");
  a.spacing_search_ratio = r.number("spacing_search_ratio", a.spacing_search_ratio, ParamRange::closed(1.0, 2.0));
  a.spacing_fit_tolerance_m = r.number("spacing_fit_tolerance_m", a.spacing_fit_tolerance_m, positive, "m");
  a.row_heading_tolerance_rad =
      r.number("row_heading_tolerance_rad", a.row_heading_tolerance_rad, ParamRange{0.0, 0.2, true, true}, "rad");
  a.edge_straightness_m = r.number("edge_straightness_m", a.edge_straightness_m, positive, "m");
  a.side_wall_min_support = r.number("side_wall_min_support", a.side_wall_min_support, ParamRange::aboveUpTo(0.0, 1.0));
  a.side_wall_max_thickness_m =
      r.number("side_wall_max_thickness_m", a.side_wall_max_thickness_m, ParamRange::atLeast(0.0), "m");
  r.alsoRead("diagnostic_period");
  // Checks across parameters (e.g. the gauge below the spacing): the library's own validation.
  if (const std::string error = a.validate(); !error.empty())
    throw thorvald_common::ParamError(r.node() + ": " + error);
  if (s.frame_id.empty()) throw thorvald_common::ParamError(r.node() + ": frame_id must not be empty");
  r.finish();
  return s;
}

class MapAnalyzerNode {
 public:
  MapAnalyzerNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeSettings& settings)
      : settings_(settings), updater_(nh, pnh) {
    targets_pub_ = nh.advertise<geometry_msgs::PoseArray>("rail_targets", 1, true);
    uncertain_pub_ = nh.advertise<geometry_msgs::PoseArray>("rail_targets_uncertain", 1, true);
    frames_pub_ = nh.advertise<geometry_msgs::PoseArray>("rail_frames", 1, true);
    edge_pub_ = nh.advertise<geometry_msgs::PolygonStamped>("headland_edge", 1, true);
    keep_out_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("keep_out_map", 1, true);
    markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
    status_pub_ = pnh.advertise<std_msgs::String>("status", 1, true);
    updater_.setHardwareID("map_analyzer");
    updater_.add("map analysis", this, &MapAnalyzerNode::diagnose);
    diag_timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { updater_.update(); });
  }

  void subscribe(ros::NodeHandle& nh) { map_sub_ = nh.subscribe("map", 1, &MapAnalyzerNode::onMap, this); }

  void onMap(const nav_msgs::OccupancyGrid::ConstPtr& msg) {
    if (static_cast<std::uint64_t>(msg->info.width) * msg->info.height >
        static_cast<std::uint64_t>(settings_.max_map_cells)) {
      ++rejected_maps_;
      std_msgs::String s;
      s.data = "rejected: map of " + std::to_string(msg->info.width) + " x " + std::to_string(msg->info.height) +
               " cells is larger than max_map_cells (" + std::to_string(settings_.max_map_cells) + ")";
      ROS_ERROR_STREAM("map_analyzer: " << s.data);
      status_pub_.publish(s);
      return;
    }
    thorvald_map::OccupancyGrid map;
    std::string error;
    if (!thorvald_map::fromGridMessage(*msg, &map, &error)) {
      ++rejected_maps_;
      std_msgs::String s;
      s.data = "rejected: map message: " + error;
      ROS_ERROR_STREAM("map_analyzer: " << s.data);
      status_pub_.publish(s);
      return;
    }
    analyze(map, msg->header.frame_id.empty() ? settings_.frame_id : msg->header.frame_id);
  }

  void analyze(const thorvald_map::OccupancyGrid& map, const std::string& frame_id) {
    const auto t0 = std::chrono::steady_clock::now();
    const MapAnalysis analysis = analyzeMap(map, settings_.analysis);
    last_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ++analyses_;
    ok_ = analysis.ok;
    status_ = analysis.status;
    uncertain_reasons_ = analysis.uncertain_reasons;
    confidence_ = analysis.confidence;
    sets_ = analysis.rail_sets.size();
    good_sets_ = 0;
    for (const auto& set : analysis.rail_sets) good_sets_ += set.good;
    warnings_ = analysis.warnings.size();
    last_message_ = analysis.message;
    const ros::Time stamp = ros::Time::now();
    geometry_msgs::PoseArray targets, frames;
    targets.header.frame_id = frames.header.frame_id = frame_id;
    targets.header.stamp = frames.header.stamp = stamp;
    geometry_msgs::PoseArray uncertain = targets;
    for (const auto& set : analysis.rail_sets) {  // empty when nothing usable was found: no invented poses
      // Only good sets go where a mission looks; uncertain ones are published apart for a person to check.
      (set.good ? targets : uncertain).poses.push_back(thorvald_map::toPose(set.target_pose));
      if (set.good) frames.poses.push_back(thorvald_map::toPose(set.rail_frame));
    }
    uncertain_pub_.publish(uncertain);
    markers_pub_.publish(analysisMarkers(analysis, settings_.analysis.rail_gauge_m, frame_id, stamp));
    if (analysis.ok) {
      ROS_INFO_STREAM("map_analyzer: " << analysis.message);
      if (analysis.status == MapStatus::kUncertain)
        ROS_WARN_STREAM("map_analyzer: uncertain: " << analysis.uncertain_reasons);
      for (const auto& w : analysis.warnings) ROS_WARN_STREAM("map_analyzer: " << w);
      geometry_msgs::PolygonStamped edge;
      edge.header = targets.header;
      for (const auto& p : {analysis.edge_start, analysis.edge_end}) {
        geometry_msgs::Point32 q;
        q.x = static_cast<float>(p.x());
        q.y = static_cast<float>(p.y());
        edge.polygon.points.push_back(q);
      }
      edge_pub_.publish(edge);
      keep_out_pub_.publish(
          thorvald_map::toGridMessage(makeKeepOutGrid(map, analysis.edge_start, analysis.edge_end, analysis.into_rows,
                                                      settings_.analysis.keep_out_margin_m),
                                      frame_id, stamp));
      writeFile(analysis, frame_id);
      if (!settings_.overlay_png.empty()) {
        std::string error;
        if (writeMapOverlayPng(map, analysis, settings_.overlay_png, &error, settings_.analysis.keep_out_margin_m)) {
          ROS_INFO_STREAM("map_analyzer: wrote the overlay " << settings_.overlay_png);
        } else {
          ROS_ERROR_STREAM("map_analyzer: " << error);
        }
      }
    } else {
      ROS_ERROR_STREAM("map_analyzer: no rail sets: " << analysis.message);
    }
    frames_pub_.publish(frames);
    targets_pub_.publish(targets);
    publishStatus();
    updater_.force_update();
  }

 private:
  void writeFile(const MapAnalysis& analysis, const std::string& frame_id) {
    if (settings_.output_file.empty()) return;
    RailSetFile file;
    file.frame_id = frame_id;
    file.status = toString(analysis.status);
    file.confidence = analysis.confidence;
    file.reasons = analysis.uncertain_reasons;
    file.rail_sets = analysis.rail_sets;
    file.edge_start = analysis.edge_start;
    file.edge_end = analysis.edge_end;
    file.into_rows = analysis.into_rows;
    std::string error;
    file_error_.clear();
    if (!saveRailSetFile(file, settings_.output_file, &error)) {
      file_error_ = error;
      ROS_ERROR_STREAM("map_analyzer: " << error);
    } else {
      ROS_INFO_STREAM("map_analyzer: wrote " << analysis.rail_sets.size() << " rail sets to " << settings_.output_file);
    }
  }

  void publishStatus() {
    std_msgs::String s;
    s.data = std::string(toString(status_)) + ": " + last_message_;
    if (status_ == MapStatus::kUncertain) s.data += "; uncertain because: " + uncertain_reasons_;
    status_pub_.publish(s);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    using diagnostic_msgs::DiagnosticStatus;
    if (analyses_ == 0) {
      stat.summary(DiagnosticStatus::WARN, "waiting for a map");
    } else if (!ok_) {
      stat.summary(DiagnosticStatus::ERROR, last_message_);
    } else if (!file_error_.empty()) {
      stat.summary(DiagnosticStatus::ERROR, file_error_);
    } else if (status_ == MapStatus::kUncertain) {
      stat.summary(DiagnosticStatus::WARN, "uncertain: " + uncertain_reasons_);
    } else {
      stat.summary(warnings_ ? DiagnosticStatus::WARN : DiagnosticStatus::OK, last_message_);
    }
    stat.add("analyses", analyses_);
    stat.add("rejected maps", rejected_maps_);
    stat.add("rail sets", sets_);
    stat.add("good rail sets", good_sets_);
    stat.add("confidence", confidence_);
    stat.add("warnings", warnings_);
    stat.add("analysis time [ms]", last_ms_);
    stat.add("output file", settings_.output_file);
  }

  NodeSettings settings_;
  diagnostic_updater::Updater updater_;
  ros::Publisher targets_pub_, uncertain_pub_, frames_pub_, edge_pub_, keep_out_pub_, markers_pub_, status_pub_;
  ros::Subscriber map_sub_;
  ros::Timer diag_timer_;
  std::size_t analyses_ = 0, rejected_maps_ = 0, sets_ = 0, good_sets_ = 0, warnings_ = 0;
  bool ok_ = false;
  MapStatus status_ = MapStatus::kFailed;
  std::string uncertain_reasons_;
  double confidence_ = 0.0;
  double last_ms_ = 0.0;
  std::string last_message_, file_error_;
};

}  // namespace
}  // namespace greenhouse_rail_nav

int main(int argc, char** argv) {
  using namespace greenhouse_rail_nav;
  ros::init(argc, argv, "map_analyzer");
  ros::NodeHandle nh, pnh("~");
  NodeSettings settings;
  try {
    settings = loadSettings(pnh);
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL_STREAM("map_analyzer: cannot start: " << e.what());
    return 1;
  }
  MapAnalyzerNode node(nh, pnh, settings);
  if (!settings.map_file.empty()) {
    std::string error;
    thorvald_map::OccupancyGrid map;
    thorvald_map::MapLoadOptions limits;
    limits.max_cells = static_cast<std::uint64_t>(settings.max_map_cells);
    if (!thorvald_map::loadMap(settings.map_file, &map, &error, limits)) {
      ROS_FATAL_STREAM("map_analyzer: cannot start: " << error);
      return 1;
    }
    node.analyze(map, settings.frame_id);
  } else {
    node.subscribe(nh);
  }
  ros::spin();
  return 0;
}
