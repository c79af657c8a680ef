#include "cotton_harvester/perception/colour_boll_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {
namespace {

/// A maximum of a region's distance transform: the centre and radius of a disc inscribed in the region.
struct Peak {
  cv::Point2f centre;  ///< region-local pixel
  float radius = 0.0f;
};

/// Smallest distance-transform value on the segment between two points: the region's half width at its neck.
float neckBetween(const cv::Mat& dist, const cv::Point2f& a, const cv::Point2f& b) {
  const int samples = std::max(2, static_cast<int>(std::ceil(cv::norm(b - a))));
  float neck = std::numeric_limits<float>::infinity();
  for (int i = 0; i <= samples; ++i) {
    const cv::Point2f p = a + (b - a) * (static_cast<float>(i) / samples);
    neck = std::min(neck, dist.at<float>(cvRound(p.y), cvRound(p.x)));
  }
  return neck;
}

/// Maxima of the distance transform that stand for separate bolls: local maxima at least min_radius deep, strongest
/// first, kept when they lie outside every kept disc and a neck narrower than neck_ratio of the smaller radius
/// separates them from every kept one.
std::vector<Peak> findPeaks(const cv::Mat& dist, double min_radius, double neck_ratio, int window) {
  cv::Mat dilated;
  cv::dilate(dist, dilated, cv::getStructuringElement(cv::MORPH_RECT, {window, window}));
  std::vector<Peak> candidates;
  for (int v = 0; v < dist.rows; ++v) {
    const float* d = dist.ptr<float>(v);
    const float* m = dilated.ptr<float>(v);
    for (int u = 0; u < dist.cols; ++u)
      if (d[u] >= m[u] && d[u] >= min_radius) candidates.push_back({cv::Point2f(u, v), d[u]});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Peak& a, const Peak& b) { return a.radius > b.radius; });
  constexpr size_t kMaxCandidates = 64;  // a plateau gives many equal maxima; the strongest few decide
  if (candidates.size() > kMaxCandidates) candidates.resize(kMaxCandidates);
  std::vector<Peak> kept;
  for (const Peak& candidate : candidates) {
    const bool separate = std::all_of(kept.begin(), kept.end(), [&](const Peak& other) {
      // Two touching bolls have their centres about the sum of their radii apart; lobes of one boll are closer.
      if (cv::norm(candidate.centre - other.centre) < 0.8 * (candidate.radius + other.radius)) return false;
      const float smaller = std::min(candidate.radius, other.radius);
      return neckBetween(dist, candidate.centre, other.centre) < neck_ratio * smaller;
    });
    if (separate) kept.push_back(candidate);
  }
  return kept;
}

/// Share of its disc that a whole boll's white lint covers: about 0.88 (the outer 6 % of its radius are brown
/// bracts), a little less with the creases between its lobes. A boll showing less is partly hidden.
constexpr double kWholeWhiteShare = 0.75;

/// Outline points that can be the silhouette of a boll whose disc holds the inscribed disc (centre, radius): a disc
/// that holds it has its outline between radius and about twice the boll's radius minus it from the centre, and a
/// circle's outline runs across the direction to any point inside it, most nearly so for one that lies near its
/// centre. Kept: points within 1.6 radii (a boll's own disc is at most about 1.3 times the inscribed one when most
/// of it is visible) whose outline runs within 30 degrees of across that direction; the outline of another boll
/// beside it or of a thin thing joined to it runs along it.
std::vector<cv::Point2d> lobeOutline(const std::vector<cv::Point>& outline, const cv::Point2d& centre, double radius) {
  std::vector<cv::Point2d> points;
  const int n = static_cast<int>(outline.size());
  const int k = std::max(2, static_cast<int>(std::lround(0.25 * radius)));  // tangent over +-k outline pixels
  if (n < 2 * k + 1) return points;
  const double reach = 1.6 * radius + 1.0;
  for (int i = 0; i < n; ++i) {
    const cv::Point2d d = cv::Point2d(outline[i]) - centre;
    const double distance = std::hypot(d.x, d.y);
    if (distance > reach || distance <= 0.0) continue;
    const cv::Point2d t = cv::Point2d(outline[(i + k) % n] - outline[(i - k + n) % n]);
    const double length = std::hypot(t.x, t.y);
    if (length > 0.0 && std::abs(t.dot(d)) <= 0.5 * length * distance) points.push_back(cv::Point2d(outline[i]));
  }
  return points;
}

}  // namespace

std::string validate(const ColourBollParams& p) {
  std::ostringstream error;
  if (p.value_min < 0 || p.value_min > 255) error << "value_min must be in [0, 255] (got " << p.value_min << "); ";
  if (p.saturation_max < 0 || p.saturation_max > 255)
    error << "saturation_max must be in [0, 255] (got " << p.saturation_max << "); ";
  if (!(p.value_contrast >= 1.0 && p.value_contrast <= 5.0))
    error << "value_contrast must be in [1, 5] (got " << p.value_contrast << "); ";
  if (p.value_floor < 0 || p.value_floor > p.value_min)
    error << "value_floor must be in [0, value_min] (got " << p.value_floor << "); ";
  if (!(p.opening_fraction >= 0.0 && p.opening_fraction <= 2.0))
    error << "opening_fraction must be in [0, 2] (got " << p.opening_fraction << "); ";
  if (!(p.closing_fraction >= 0.0 && p.closing_fraction <= 2.0))
    error << "closing_fraction must be in [0, 2] (got " << p.closing_fraction << "); ";
  if (!(p.partial_min_visible >= 0.0 && p.partial_min_visible <= 1.0))
    error << "partial_min_visible must be in [0, 1] (got " << p.partial_min_visible << "); ";
  if (!(p.circle_max_rms_fraction > 0.0 && p.circle_max_rms_fraction <= 1.0))
    error << "circle_max_rms_fraction must be in (0, 1] (got " << p.circle_max_rms_fraction << "); ";
  if (!(p.circle_min_arc_deg >= 0.0 && p.circle_min_arc_deg <= 360.0))
    error << "circle_min_arc_deg must be in [0, 360] (got " << p.circle_min_arc_deg << "); ";
  if (!(p.partial_min_fraction >= 0.0 && p.partial_min_fraction <= 1.0))
    error << "partial_min_fraction must be in [0, 1] (got " << p.partial_min_fraction << "); ";
  if (!(p.min_visible_fraction > 0.0 && p.min_visible_fraction <= 1.0))
    error << "min_visible_fraction must be in (0, 1] (got " << p.min_visible_fraction << "); ";
  if (p.max_cluster_bolls < 1 || p.max_cluster_bolls > 100)
    error << "max_cluster_bolls must be in [1, 100] (got " << p.max_cluster_bolls << "); ";
  if (!(p.min_circularity >= 0.0 && p.min_circularity <= 1.0))
    error << "min_circularity must be in [0, 1] (got " << p.min_circularity << "); ";
  if (!(p.min_solidity >= 0.0 && p.min_solidity <= 1.0))
    error << "min_solidity must be in [0, 1] (got " << p.min_solidity << "); ";
  if (!(p.max_aspect_ratio >= 1.0)) error << "max_aspect_ratio must be >= 1 (got " << p.max_aspect_ratio << "); ";
  if (!(p.split_neck_ratio >= 0.0 && p.split_neck_ratio <= 1.0))
    error << "split_neck_ratio must be in [0, 1] (got " << p.split_neck_ratio << "); ";
  return error.str();
}

ColourBollDetector::ColourBollDetector(const ColourBollParams& params) : params_(params) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("colour boll detector parameters: " + error);
  setGeometry(CameraIntrinsics{}, BollGeometry{});
}

void ColourBollDetector::setGeometry(const CameraIntrinsics& intrinsics, const BollGeometry& geometry) {
  const std::string error = validate(intrinsics) + validate(geometry);
  if (!error.empty()) throw std::invalid_argument("colour boll detector geometry: " + error);
  const PixelRadiusRange radius = bollRadiusPx(geometry, 0.5 * (intrinsics.fx + intrinsics.fy));
  scale_.radius_min_px = radius.min_px;
  scale_.radius_max_px = radius.max_px;
  const double smallest_disc = CV_PI * radius.min_px * radius.min_px;
  const double largest_disc = CV_PI * radius.max_px * radius.max_px;
  scale_.min_area_px = std::max(4.0, params_.min_visible_fraction * smallest_disc);
  scale_.partial_min_area_px = std::max(scale_.min_area_px, params_.partial_min_fraction * smallest_disc);
  scale_.max_single_area_px = 1.3 * largest_disc;
  scale_.max_area_px = params_.max_cluster_bolls * largest_disc;
  // Odd sides, so that the structuring elements are centred and do not move the regions.
  const auto odd = [](double side) { return 2 * static_cast<int>(std::lround(0.5 * (side - 1.0))) + 1; };
  scale_.opening_px = odd(params_.opening_fraction * radius.min_px);
  scale_.closing_px = odd(params_.closing_fraction * radius.min_px);
}

void ColourBollDetector::detectRegion(const std::vector<cv::Point>& contour, const cv::Mat& bgr, const cv::Mat& mask,
                                      int peels_left, std::vector<BollDetection>* bolls) const {
  const double area = cv::contourArea(contour);
  if (area < scale_.min_area_px || area > scale_.max_area_px) return;
  const cv::Rect box = cv::boundingRect(contour);
  const cv::Scalar mean_bgr = cv::mean(bgr(box), mask(box));
  const double brightness = std::max({mean_bgr[0], mean_bgr[1], mean_bgr[2]}) / 255.0;

  // The region alone, with a border so that the distance transform sees its edge everywhere. Closing it first fills
  // the dark creases between a boll's lobes, which would otherwise make one boll look like several.
  const int close_px = std::max(3, 2 * static_cast<int>(0.35 * scale_.radius_min_px) + 1);
  const int pad = close_px + 1;
  const cv::Point origin(box.x - pad, box.y - pad);  // image pixel of the region image's (0, 0)
  cv::Mat region = cv::Mat::zeros(box.height + 2 * pad, box.width + 2 * pad, CV_8U);
  const std::vector<std::vector<cv::Point>> one{contour};
  cv::drawContours(region, one, 0, cv::Scalar(255), cv::FILLED, cv::LINE_8, cv::noArray(), INT_MAX, -origin);
  cv::Mat closed;
  cv::morphologyEx(region, closed, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_ELLIPSE, {close_px, close_px}));
  cv::Mat dist;
  cv::distanceTransform(closed, dist, cv::DIST_L2, cv::DIST_MASK_5);
  const int window = 2 * std::max(1, static_cast<int>(0.5 * scale_.radius_min_px)) + 1;
  const std::vector<Peak> peaks =
      findPeaks(dist, std::max(1.5, 0.4 * scale_.radius_min_px), params_.split_neck_ratio, window);

  if (peaks.size() <= 1) {
    if (area > scale_.max_single_area_px) return;
    const double perimeter = cv::arcLength(contour, true);
    const double circularity = perimeter > 0.0 ? std::min(1.0, 4.0 * CV_PI * area / (perimeter * perimeter)) : 0.0;
    std::vector<cv::Point> hull;
    cv::convexHull(contour, hull);
    const double hull_area = cv::contourArea(hull);
    const double solidity = hull_area > 0.0 ? area / hull_area : 0.0;
    // Aspect of the smallest rotated rectangle: a thin glint at 45 degrees has a square bounding box.
    const cv::Size2f rotated = cv::minAreaRect(contour).size;
    const double aspect =
        std::max(rotated.width, rotated.height) / std::max(1.0f, std::min(rotated.width, rotated.height));
    const bool whole = circularity >= params_.min_circularity && solidity >= params_.min_solidity &&
                       aspect <= params_.max_aspect_ratio;
    // The boll's own silhouette: a circle through the outline's hull points (a leaf's cut runs inside the hull).
    const std::optional<BollCircle> circle = roundOutline(contour);
    const double disc_share = circle ? area / (CV_PI * circle->radius_px * circle->radius_px) : 0.0;
    const bool hidden_boll = !whole && circle && params_.partial_min_visible > 0.0 &&
                             disc_share >= params_.partial_min_visible && disc_share <= 1.15;
    // Not one round boll: a boll joined to something else by the closing or by touching it (another boll that the
    // distance transform does not tell apart, the sliver of one behind it, a glint, a label). The boll around the
    // distance transform's maximum is taken out on its own circle and the rest is looked at again.
    if (!peaks.empty() && !hidden_boll && !(whole && circle) && peels_left > 0) {
      const cv::Point2d peak(origin.x + peaks[0].centre.x, origin.y + peaks[0].centre.y);
      if (peelBoll(contour, region, origin, peak, peaks[0].radius, brightness, bgr, mask, peels_left, bolls)) return;
    }
    bool partial = !whole && params_.partial_min_fraction > 0.0 && area >= scale_.partial_min_area_px;
    if (partial) {  // a part of one boll fits inside the largest boll's disc
      cv::Point2f centre;
      float radius = 0.0f;
      cv::minEnclosingCircle(contour, centre, radius);
      partial = radius <= scale_.radius_max_px;
    }
    if (whole && params_.whole_needs_arc && !circle) return;
    if (!whole && !partial && !hidden_boll) return;
    const cv::Moments m = cv::moments(contour);
    BollDetection boll;
    boll.box = box;
    boll.centroid = {m.m10 / m.m00, m.m01 / m.m00};
    if (whole || hidden_boll) {
      boll.confidence = std::clamp((whole ? circularity * solidity : disc_share) * brightness, 0.0, 1.0);
    } else {
      boll.confidence = std::clamp(circularity * solidity * brightness * 0.3, 0.0, 1.0);
    }
    boll.partial = !whole;
    boll.centre = circle ? circle->centre : boll.centroid;
    boll.radius_px = circle ? circle->radius_px : std::sqrt(area / CV_PI);
    boll.outline = contour;
    bolls->push_back(std::move(boll));
    return;
  }

  // Touching bolls: each pixel of the region goes to the peak whose disc edge is nearest.
  struct Part {
    double count = 0.0, sum_u = 0.0, sum_v = 0.0;
    int u_min = INT_MAX, v_min = INT_MAX, u_max = -1, v_max = -1;
  };
  std::vector<Part> parts(peaks.size());
  cv::Mat owner = cv::Mat::zeros(region.size(), CV_8U);  // 1 + the part's index, 0 outside the region
  for (int v = pad; v < pad + box.height; ++v) {
    const uint8_t* inside = region.ptr<uint8_t>(v);
    uint8_t* owned = owner.ptr<uint8_t>(v);
    for (int u = pad; u < pad + box.width; ++u) {
      if (!inside[u]) continue;
      size_t best = 0;
      double best_cost = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < peaks.size(); ++i) {
        const double cost = std::hypot(u - peaks[i].centre.x, v - peaks[i].centre.y) - peaks[i].radius;
        if (cost < best_cost) {
          best_cost = cost;
          best = i;
        }
      }
      owned[u] = static_cast<uint8_t>(best + 1);
      Part& part = parts[best];
      part.count += 1.0;
      part.sum_u += u;
      part.sum_v += v;
      part.u_min = std::min(part.u_min, u);
      part.u_max = std::max(part.u_max, u);
      part.v_min = std::min(part.v_min, v);
      part.v_max = std::max(part.v_max, v);
    }
  }
  for (size_t i = 0; i < parts.size(); ++i) {
    const Part& part = parts[i];
    if (part.count < scale_.min_area_px || part.count > scale_.max_single_area_px) continue;
    const int width = part.u_max - part.u_min + 1, height = part.v_max - part.v_min + 1;
    if (static_cast<double>(std::max(width, height)) / std::min(width, height) > params_.max_aspect_ratio) continue;
    BollDetection boll;
    boll.box = cv::Rect2d(origin.x + part.u_min, origin.y + part.v_min, width, height);
    boll.centroid = {origin.x + part.sum_u / part.count, origin.y + part.sum_v / part.count};
    const double fill = part.count / (CV_PI * peaks[i].radius * peaks[i].radius);
    boll.confidence = std::clamp(std::min(1.0, fill) * brightness, 0.0, 1.0);
    // The part's outline in image pixels; its circle when the part's own silhouette is round and its disc holds the
    // part's inscribed disc, else the inscribed disc (the distance transform's maximum: the boll's centre when the
    // boll is whole). A boll partly hidden behind its neighbour shows a crescent whose inscribed disc is small and
    // lies off the boll's centre, towards its visible rim, while the circle of its outer arc is the whole boll's.
    std::vector<std::vector<cv::Point>> outlines;
    cv::findContours(owner == static_cast<int>(i + 1), outlines, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, origin);
    const auto largest = std::max_element(outlines.begin(), outlines.end(),
                                          [](const auto& a, const auto& b) { return a.size() < b.size(); });
    boll.centre = {origin.x + peaks[i].centre.x, origin.y + peaks[i].centre.y};
    boll.radius_px = peaks[i].radius + 0.5;
    if (largest != outlines.end()) {
      boll.outline = std::move(*largest);
      const std::optional<BollCircle> circle = roundOutline(boll.outline);
      if (circle && holdsDisc(*circle, boll.centre, peaks[i].radius) &&
          part.count >= visibleShareMin() * CV_PI * circle->radius_px * circle->radius_px) {
        boll.centre = circle->centre;
        boll.radius_px = circle->radius_px;
      }
    }
    bolls->push_back(std::move(boll));
  }
}

bool ColourBollDetector::holdsDisc(const BollCircle& circle, const cv::Point2d& centre, double radius) const {
  // The inscribed radius comes from the closed region on the pixel grid: a pixel, or a tenth of the radius, of slack.
  return cv::norm(circle.centre - centre) + radius <= circle.radius_px + std::max(1.5, 0.1 * circle.radius_px);
}

double ColourBollDetector::visibleShareMin() const {
  // Without partly hidden bolls, a boll must show what a whole one does.
  return params_.partial_min_visible > 0.0 ? params_.partial_min_visible : kWholeWhiteShare;
}

std::optional<BollCircle> ColourBollDetector::lobeCircle(const std::vector<cv::Point>& outline,
                                                         const cv::Point2d& centre, double radius) const {
  const std::vector<cv::Point2d> candidates = lobeOutline(outline, centre, radius);
  if (candidates.size() < 8) return std::nullopt;
  // Robust refit: the candidates within a tolerance of the previous circle (the outline of another boll or of a
  // sliver that passes the direction test lies off it); the tolerance is the roundness a boll's outline is allowed.
  std::optional<BollCircle> circle = fitCircle(candidates);
  std::vector<cv::Point2d> on_circle;
  for (int round = 0; round < 3 && circle; ++round) {
    const double tolerance = std::max(1.5, 2.0 * params_.circle_max_rms_fraction * circle->radius_px);
    on_circle.clear();
    for (const cv::Point2d& p : candidates)
      if (std::abs(cv::norm(p - circle->centre) - circle->radius_px) <= tolerance) on_circle.push_back(p);
    if (on_circle.size() < 8) return std::nullopt;
    circle = fitCircle(on_circle);
  }
  if (!circle) return std::nullopt;
  circle->radius_px += 0.5;  // boundary pixel centres lie half a pixel inside the region's edge
  const bool round = circle->rms_px <= std::max(0.75, params_.circle_max_rms_fraction * circle->radius_px) &&
                     circle->arc_coverage_rad >= params_.circle_min_arc_deg * CV_PI / 180.0;
  const bool boll_sized =
      circle->radius_px >= 0.7 * scale_.radius_min_px && circle->radius_px <= 1.2 * scale_.radius_max_px;
  if (!round || !boll_sized || !holdsDisc(*circle, centre, radius)) return std::nullopt;
  return circle;
}

bool ColourBollDetector::peelBoll(const std::vector<cv::Point>& contour, const cv::Mat& region, const cv::Point& origin,
                                  const cv::Point2d& peak, double peak_radius, double brightness, const cv::Mat& bgr,
                                  const cv::Mat& mask, int peels_left, std::vector<BollDetection>* bolls) const {
  const std::optional<BollCircle> circle = lobeCircle(contour, peak, peak_radius);
  if (!circle) return false;
  // What else the region holds is joined to the boll by a neck, as touching bolls are (split_neck_ratio): where the
  // region crosses the circle just outside the boll's edge, its half width stays under split_neck_ratio of the boll's
  // radius. A region that goes on past the circle as wide as the boll (a crescent past a leaf, whose thick part holds
  // a smaller circle than its boll's; a long bag whose end is round) is not a boll with something joined to it.
  const double rim = circle->radius_px + 1.5;
  const int samples = static_cast<int>(std::ceil(2.0 * CV_PI * rim));
  std::vector<char> crossing(samples);
  for (int k = 0; k < samples; ++k) {
    const double angle = 2.0 * CV_PI * k / samples;
    const int u = static_cast<int>(std::lround(circle->centre.x - origin.x + rim * std::cos(angle)));
    const int v = static_cast<int>(std::lround(circle->centre.y - origin.y + rim * std::sin(angle)));
    crossing[k] = u >= 0 && v >= 0 && u < region.cols && v < region.rows && region.at<uint8_t>(v, u) != 0;
  }
  int longest = 0;
  for (int k = 0, run = 0; k < 2 * samples; ++k) {  // twice around: a run may wrap
    run = crossing[k % samples] ? run + 1 : 0;
    longest = std::max(longest, std::min(run, samples));
  }
  const double run_angle = 2.0 * CV_PI * longest / samples;
  const double half_width = run_angle >= CV_PI ? rim : rim * std::sin(0.5 * run_angle);
  if (half_width > params_.split_neck_ratio * circle->radius_px) return false;
  // The boll: the region's pixels on its disc (sub-pixel centre and radius: 4 fractional bits).
  const auto fixed = [](double x) { return static_cast<int>(std::lround(16.0 * x)); };
  const cv::Point centre16(fixed(circle->centre.x - origin.x), fixed(circle->centre.y - origin.y));
  cv::Mat own = cv::Mat::zeros(region.size(), CV_8U);
  cv::circle(own, centre16, fixed(circle->radius_px + 0.5), cv::Scalar(255), cv::FILLED, cv::LINE_8, 4);
  own &= region;
  const cv::Moments m = cv::moments(own, true);
  const double disc_area = CV_PI * circle->radius_px * circle->radius_px;
  const double share = m.m00 / disc_area;
  if (m.m00 < scale_.min_area_px || share < visibleShareMin()) return false;
  std::vector<std::vector<cv::Point>> outlines;
  cv::findContours(own, outlines, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, origin);
  const auto largest = std::max_element(outlines.begin(), outlines.end(),
                                        [](const auto& a, const auto& b) { return a.size() < b.size(); });
  if (largest == outlines.end()) return false;
  BollDetection boll;
  boll.outline = std::move(*largest);
  boll.box = cv::boundingRect(boll.outline);
  boll.centroid = {origin.x + m.m10 / m.m00, origin.y + m.m01 / m.m00};
  boll.confidence = std::clamp(std::min(1.0, share) * brightness, 0.0, 1.0);
  boll.partial = share < kWholeWhiteShare;
  boll.centre = circle->centre;
  boll.radius_px = circle->radius_px;
  bolls->push_back(std::move(boll));

  // The rest of the region, off this boll's disc (and a pixel beyond its edge, which mixes it with what borders it),
  // cleaned of the slivers that its rim leaves: regions of their own.
  cv::Mat rest = region.clone();
  cv::circle(rest, centre16, fixed(circle->radius_px + 1.5), cv::Scalar(0), cv::FILLED, cv::LINE_8, 4);
  if (scale_.opening_px > 1)
    cv::morphologyEx(rest, rest, cv::MORPH_OPEN,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, {scale_.opening_px, scale_.opening_px}));
  std::vector<std::vector<cv::Point>> others;
  cv::findContours(rest, others, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, origin);
  for (const std::vector<cv::Point>& other : others) detectRegion(other, bgr, mask, peels_left - 1, bolls);
  return true;
}

std::optional<BollCircle> ColourBollDetector::roundOutline(const std::vector<cv::Point>& outline) const {
  std::optional<BollCircle> circle = fitOuterCircle(outline);
  if (!circle) return std::nullopt;
  const bool round = circle->rms_px <= std::max(0.75, params_.circle_max_rms_fraction * circle->radius_px) &&
                     circle->arc_coverage_rad >= params_.circle_min_arc_deg * CV_PI / 180.0;
  // A boll's radius at some allowed height (the white part of a boll ends a little inside its silhouette).
  const bool boll_sized =
      circle->radius_px >= 0.7 * scale_.radius_min_px && circle->radius_px <= 1.2 * scale_.radius_max_px;
  if (!round || !boll_sized) return std::nullopt;
  return circle;
}

int ColourBollDetector::valueThreshold(const cv::Mat& bgr) const {
  // Median brightness (HSV value = largest channel) of the scene, from every fourth pixel of every fourth row.
  int histogram[256] = {0};
  int count = 0;
  for (int v = 0; v < bgr.rows; v += 4) {
    const cv::Vec3b* pixel = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < bgr.cols; u += 4, ++count) ++histogram[std::max({pixel[u][0], pixel[u][1], pixel[u][2]})];
  }
  int median = 0;
  for (int seen = 0; median < 255; ++median) {
    seen += histogram[median];
    if (2 * seen >= count) break;
  }
  const int relative = static_cast<int>(std::lround(params_.value_contrast * median));
  return std::clamp(relative, params_.value_floor, params_.value_min);
}

std::vector<BollDetection> ColourBollDetector::detect(const cv::Mat& bgr, const cv::Mat& exclude) {
  std::vector<BollDetection> bolls;
  if (bgr.empty() || bgr.type() != CV_8UC3) return bolls;

  cv::Mat mask = whitePixels(bgr, valueThreshold(bgr), params_.saturation_max);
  if (!exclude.empty() && exclude.size() == mask.size() && exclude.type() == CV_8U) mask.setTo(0, exclude);
  if (scale_.opening_px > 1) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {scale_.opening_px, scale_.opening_px});
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, kernel);
  }
  // A twig or a leaf's edge across a boll cuts it in two: closing over a stem's width joins the pieces (bolls that
  // are joined this way are split again by their distance-transform maxima).
  if (scale_.closing_px > 1) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {scale_.closing_px, scale_.closing_px});
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, kernel);
    if (!exclude.empty() && exclude.size() == mask.size() && exclude.type() == CV_8U) mask.setTo(0, exclude);
  }

  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  for (const std::vector<cv::Point>& contour : contours)
    detectRegion(contour, bgr, mask, params_.max_cluster_bolls, &bolls);
  return bolls;
}

}  // namespace perception
}  // namespace cotton_harvester
