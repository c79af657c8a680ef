#pragma once

#include <optional>
#include <ostream>
#include <string>

namespace cotton_harvester {
namespace control {

/// What a run counted (paper §2.13, Tables 2–3 columns).
struct HarvestCounts {
  int bolls_present = 0;    ///< ground truth when known (0: unknown, ratios use the bolls detected)
  int detected = 0;         ///< distinct bolls seen
  int reached = 0;          ///< bolls the arm reached and tried to pick
  int picked = 0;           ///< bolls removed
  int skipped = 0;          ///< bolls given up after their retries
  int pick_attempts = 0;    ///< pick actions, successful or not
  double time_s = 0.0;      ///< duration of the run
  double distance_m = 0.0;  ///< distance the rover covered
};

/// The paper's performance figures. Ratios in percent; absent when their denominator is zero.
struct HarvestMetrics {
  double operation_velocity_cm_s = 0.0;             ///< OV = distance / time
  double production_rate_bolls_s = 0.0;             ///< PR = picked / time
  std::optional<double> cycle_time_s;               ///< CT = time / picked
  std::optional<double> action_success_pct;         ///< ASR = picked / bolls present
  std::optional<double> detection_performance_pct;  ///< DP = detected / bolls present
  std::optional<double> reaching_ratio_pct;         ///< MRR = reached / bolls present
};

HarvestMetrics computeMetrics(const HarvestCounts& counts);

/// CSV with one row per run; the header is written when the file is new or empty.
std::string csvHeader();
std::string csvRow(const std::string& run, const HarvestCounts& counts, const HarvestMetrics& metrics);
/// Appends a row to `path`; false (with `error`) when the file cannot be written.
bool appendCsv(const std::string& path, const std::string& run, const HarvestCounts& counts,
               const HarvestMetrics& metrics, std::string* error);

}  // namespace control
}  // namespace cotton_harvester
