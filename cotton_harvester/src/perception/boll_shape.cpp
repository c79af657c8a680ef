#include "cotton_harvester/perception/boll_shape.h"

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {

RegionShape measureRegionShape(const std::vector<cv::Point>& contour, double area_px) {
  RegionShape shape;
  const double perimeter = cv::arcLength(contour, true);
  shape.circularity = perimeter > 0.0 ? std::min(1.0, 4.0 * CV_PI * area_px / (perimeter * perimeter)) : 0.0;
  std::vector<cv::Point> hull;
  cv::convexHull(contour, hull);
  const double hull_area = cv::contourArea(hull);
  shape.solidity = hull_area > 0.0 ? area_px / hull_area : 0.0;
  const cv::Size2f rotated = cv::minAreaRect(contour).size;
  shape.aspect = std::max(rotated.width, rotated.height) / std::max(1.0f, std::min(rotated.width, rotated.height));
  return shape;
}

}  // namespace perception
}  // namespace cotton_harvester
