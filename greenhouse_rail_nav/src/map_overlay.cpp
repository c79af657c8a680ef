#include "greenhouse_rail_nav/map_overlay.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace greenhouse_rail_nav {

bool writeMapOverlayPng(const thorvald_map::OccupancyGrid& map, const MapAnalysis& analysis, const std::string& path,
                        std::string* error, double keep_out_margin_m, int max_pixels) {
  if (map.width <= 0 || map.height <= 0 || map.data.size() != static_cast<std::size_t>(map.width) * map.height) {
    *error = "map overlay: empty or malformed map";
    return false;
  }
  const int longest = std::max(map.width, map.height);
  double scale = std::clamp(std::floor(800.0 / longest), 1.0, 4.0);
  if (longest * scale > max_pixels) scale = static_cast<double>(max_pixels) / longest;
  cv::Mat grey(map.height, map.width, CV_8UC3);
  for (int r = 0; r < map.height; ++r) {
    for (int c = 0; c < map.width; ++c) {
      const std::int8_t v = map.at(c, map.height - 1 - r);
      const std::uint8_t g = v < 0 ? 190 : (v >= 65 ? 0 : 255);
      grey.at<cv::Vec3b>(r, c) = cv::Vec3b(g, g, g);
    }
  }
  cv::Mat img;
  cv::resize(grey, img, cv::Size(), scale, scale, scale >= 1.0 ? cv::INTER_NEAREST : cv::INTER_AREA);
  const thorvald_base::Pose2D to_grid = map.origin.inverse();
  auto px = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d g = to_grid.transformPoint(p) / map.resolution_m * scale;
    return cv::Point(static_cast<int>(std::lround(g.x())), static_cast<int>(std::lround(img.rows - g.y())));
  };
  const int thick = std::max(1, static_cast<int>(std::lround(scale)));
  auto segment = [&](const LineFit2D& f, const cv::Scalar& colour) {
    cv::line(img, px(f.centroid + f.direction * f.s_min), px(f.centroid + f.direction * f.s_max), colour, thick,
             cv::LINE_AA);
  };
  for (const int i : analysis.rows) segment(analysis.lines[static_cast<std::size_t>(i)].fit, cv::Scalar(0, 160, 0));
  if (analysis.rear_wall >= 0)
    segment(analysis.lines[static_cast<std::size_t>(analysis.rear_wall)].fit, cv::Scalar(255, 0, 0));
  const Eigen::Vector2d v = analysis.into_rows;
  if (analysis.ok) {
    cv::line(img, px(analysis.edge_start), px(analysis.edge_end), cv::Scalar(0, 0, 255), thick + 1, cv::LINE_AA);
    // Keep-out line: dashed, margin beyond the edge into the rows.
    const Eigen::Vector2d a = analysis.edge_start + keep_out_margin_m * v,
                          b = analysis.edge_end + keep_out_margin_m * v;
    const double length = (b - a).norm();
    for (double s = 0.0; s < length; s += 0.6) {
      const Eigen::Vector2d d = (b - a) / std::max(length, 1e-9);
      cv::line(img, px(a + d * s), px(a + d * std::min(length, s + 0.3)), cv::Scalar(255, 0, 255), thick, cv::LINE_AA);
    }
    for (const auto& [found, point] : {std::make_pair(analysis.left_wall_found, analysis.left_wall),
                                       std::make_pair(analysis.right_wall_found, analysis.right_wall)}) {
      if (found) cv::line(img, px(point), px(point - 2.0 * v), cv::Scalar(128, 128, 0), thick + 1, cv::LINE_AA);
    }
  }
  for (const auto& set : analysis.rail_sets) {
    const cv::Scalar colour = set.good ? cv::Scalar(0, 170, 0) : cv::Scalar(0, 140, 255);
    const thorvald_base::Pose2D& f = set.rail_frame;
    const Eigen::Vector2d o(f.x, f.y), dir(std::cos(f.yaw), std::sin(f.yaw));
    cv::arrowedLine(img, px(o), px(o + 0.8 * dir), colour, thick, cv::LINE_AA, 0, 0.3);
    const thorvald_base::Pose2D& t = set.target_pose;
    const Eigen::Vector2d to(t.x, t.y), tdir(std::cos(t.yaw), std::sin(t.yaw));
    cv::circle(img, px(to), std::max(2, static_cast<int>(0.15 / map.resolution_m * scale)), colour, thick, cv::LINE_AA);
    cv::line(img, px(to), px(to + 0.3 * tdir), colour, thick, cv::LINE_AA);
  }
  try {
    if (!cv::imwrite(path, img)) {
      *error = "map overlay: cannot write " + path;
      return false;
    }
  } catch (const cv::Exception& e) {
    *error = "map overlay: cannot write " + path + ": " + e.what();
    return false;
  }
  return true;
}

}  // namespace greenhouse_rail_nav
