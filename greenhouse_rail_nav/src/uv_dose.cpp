#include "greenhouse_rail_nav/uv_dose.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

namespace greenhouse_rail_nav {

std::string UvDoseParams::validate() const {
  if (!(lamp_power_w > 0.0) || !std::isfinite(lamp_power_w)) return "lamp_power must be > 0 W";
  if (!(lamp_length_m > 0.0) || !std::isfinite(lamp_length_m)) return "lamp_length must be > 0 m";
  if (!std::isfinite(lamp_offset_m)) return "lamp_offset must be finite [m]";
  if (!(target_dose_j_per_m > 0.0) || !std::isfinite(target_dose_j_per_m)) return "target_dose must be > 0 J/m";
  if (!(bin_m > 0.0) || !(bin_m <= lamp_length_m)) return "the dose's bin must be > 0 m and at most lamp_length";
  return {};
}

RowDose::RowDose(const UvDoseParams& params, double row_length_m)
    : params_(params),
      row_length_m_(std::max(0.0, row_length_m)),
      dose_(static_cast<std::size_t>(std::ceil(row_length_m_ / params.bin_m - 1e-9)), 0.0) {}

void RowDose::deposit(double centre_m, double energy_j) {
  const double lo = centre_m - 0.5 * params_.lamp_length_m, hi = centre_m + 0.5 * params_.lamp_length_m;
  const double per_m = energy_j / params_.lamp_length_m;  // [J/m] over the lit stretch
  const long first = std::max(0L, static_cast<long>(std::floor(lo / params_.bin_m)));
  const long last = std::min(static_cast<long>(dose_.size()) - 1, static_cast<long>(std::floor(hi / params_.bin_m)));
  for (long i = first; i <= last; ++i) {
    const double b0 = i * params_.bin_m, b1 = b0 + params_.bin_m;
    const double overlap = std::min(hi, b1) - std::max(lo, b0);
    if (overlap > 0.0) dose_[static_cast<std::size_t>(i)] += per_m * overlap / params_.bin_m;
  }
}

void RowDose::add(double from_m, double to_m, double dt_s, bool on) {
  if (!on || !(dt_s > 0.0) || !std::isfinite(from_m) || !std::isfinite(to_m)) return;
  // Sub-steps of at most a fifth of a bin keep the moving stretch's smear exact to a small fraction of a bin.
  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(to_m - from_m) / (0.2 * params_.bin_m))));
  const double energy = params_.lamp_power_w * dt_s / n;
  for (int k = 0; k < n; ++k) {
    const double s = from_m + (to_m - from_m) * (k + 0.5) / n;
    deposit(s + params_.lamp_offset_m, energy);
  }
}

double RowDose::coverage() const {
  if (dose_.empty()) return 1.0;
  double covered = 0.0;
  for (std::size_t i = 0; i < dose_.size(); ++i)
    if (dose_[i] >= params_.target_dose_j_per_m - 1e-9)
      covered += std::min(params_.bin_m, row_length_m_ - i * params_.bin_m);
  return covered / row_length_m_;
}

double RowDose::minDose() const { return dose_.empty() ? 0.0 : *std::min_element(dose_.begin(), dose_.end()); }

double RowDose::meanDose() const {
  return dose_.empty() ? 0.0 : std::accumulate(dose_.begin(), dose_.end(), 0.0) / dose_.size();
}

std::vector<std::pair<double, double>> RowDose::uncovered() const {
  std::vector<std::pair<double, double>> out;
  for (std::size_t i = 0; i < dose_.size(); ++i) {
    if (dose_[i] >= params_.target_dose_j_per_m - 1e-9) continue;
    const double a = i * params_.bin_m, b = std::min(row_length_m_, a + params_.bin_m);
    if (!out.empty() && std::abs(out.back().second - a) < 1e-9)
      out.back().second = b;
    else
      out.emplace_back(a, b);
  }
  return out;
}

UvDoseRecorder::UvDoseRecorder(const UvDoseParams& params, double row_length_m, double same_set_m)
    : params_(params), row_length_m_(row_length_m), same_set_m_(same_set_m) {}

void UvDoseRecorder::update(double t_s, double x, double y, double yaw, bool on_rails, bool lamps_on) {
  if (!std::isfinite(t_s) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw)) return;
  if (on_rails && !on_rails_) {  // onto the rails: which set?
    current_ = -1;
    for (std::size_t i = 0; i < sets_.size(); ++i)
      if (std::hypot(sets_[i].entry_x - x, sets_[i].entry_y - y) < same_set_m_) current_ = static_cast<int>(i);
    if (current_ < 0) {
      sets_.push_back(SetTrack{x, y, yaw});
      current_ = static_cast<int>(sets_.size()) - 1;
    }
    have_last_ = false;
  }
  on_rails_ = on_rails;
  if (!on_rails) return;
  SetTrack& set = sets_[static_cast<std::size_t>(current_)];
  const double s = (x - set.entry_x) * std::cos(set.entry_yaw) + (y - set.entry_y) * std::sin(set.entry_yaw);
  if (have_last_ && t_s > last_t_) set.motions.push_back({last_s_, s, t_s - last_t_, last_lamps_});
  set.farthest_m = std::max(set.farthest_m, s);
  have_last_ = true;
  last_t_ = t_s;
  last_s_ = s;
  last_lamps_ = lamps_on;
}

RowDose UvDoseRecorder::dose(std::size_t i) const {
  const SetTrack& set = sets_.at(i);
  RowDose row(params_, row_length_m_ > 0.0 ? row_length_m_ : set.farthest_m);
  for (const Motion& m : set.motions) row.add(m.from_m, m.to_m, m.dt_s, m.on);
  return row;
}

cv::Mat doseStrip(const RowDose& row, int width_px, int height_px) {
  const auto& d = row.dose();
  const int bins = std::max<int>(1, static_cast<int>(d.size()));
  const int px_per_bin = std::max(1, (width_px + bins - 1) / bins);
  cv::Mat img(height_px, bins * px_per_bin, CV_8UC3, cv::Scalar(40, 40, 40));
  const double target = row.params().target_dose_j_per_m;
  for (int i = 0; i < static_cast<int>(d.size()); ++i) {
    const double r = d[static_cast<std::size_t>(i)] / target;
    // BGR: covered green (brighter up to twice the target), short of it red -> yellow with the share reached.
    const cv::Scalar colour = r >= 1.0 - 1e-9 ? cv::Scalar(0, 140 + std::min(1.0, r - 1.0) * 115, 0)
                                              : cv::Scalar(0, 220 * std::max(0.0, r), 220);
    cv::rectangle(img, cv::Rect(i * px_per_bin, 0, px_per_bin, height_px), colour, cv::FILLED);
  }
  const double px_per_m = px_per_bin / row.params().bin_m;
  for (int m = 0; m <= static_cast<int>(row.rowLength()); ++m) {
    const int x = std::min(img.cols - 1, static_cast<int>(std::lround(m * px_per_m)));
    cv::line(img, {x, height_px - height_px / 4}, {x, height_px - 1}, cv::Scalar(255, 255, 255));
  }
  return img;
}

std::string doseReportYaml(const std::vector<SetDoseReport>& sets) {
  YAML::Emitter y;
  y << YAML::BeginMap << YAML::Key << "uv_dose" << YAML::Value << YAML::BeginSeq;
  for (const auto& s : sets) {
    if (!s.row) continue;
    const RowDose& r = *s.row;
    y << YAML::BeginMap;
    y << YAML::Key << "rail_set" << YAML::Value << s.set_index;
    y << YAML::Key << "row_length_m" << YAML::Value << r.rowLength();
    y << YAML::Key << "target_dose_j_per_m" << YAML::Value << r.params().target_dose_j_per_m;
    y << YAML::Key << "min_dose_j_per_m" << YAML::Value << std::round(r.minDose() * 10.0) / 10.0;
    y << YAML::Key << "mean_dose_j_per_m" << YAML::Value << std::round(r.meanDose() * 10.0) / 10.0;
    y << YAML::Key << "coverage_pct" << YAML::Value << std::round(r.coverage() * 1000.0) / 10.0;
    y << YAML::Key << "uncovered_m" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const auto& [a, b] : r.uncovered()) y << YAML::Flow << std::vector<double>{a, b};
    y << YAML::EndSeq;
    y << YAML::Key << "lamp_power_w" << YAML::Value << r.params().lamp_power_w;
    y << YAML::Key << "lamp_length_m" << YAML::Value << r.params().lamp_length_m;
    y << YAML::Key << "png" << YAML::Value << s.png_file;
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  return std::string(y.c_str()) + "\n";
}

}  // namespace greenhouse_rail_nav
