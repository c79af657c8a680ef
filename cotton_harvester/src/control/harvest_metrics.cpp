#include "cotton_harvester/control/harvest_metrics.h"

#include <fstream>
#include <iomanip>
#include <sstream>

namespace cotton_harvester {
namespace control {

HarvestMetrics computeMetrics(const HarvestCounts& counts) {
  HarvestMetrics metrics;
  if (counts.time_s > 0.0) {
    metrics.operation_velocity_cm_s = 100.0 * counts.distance_m / counts.time_s;
    metrics.production_rate_bolls_s = counts.picked / counts.time_s;
  }
  if (counts.picked > 0) metrics.cycle_time_s = counts.time_s / counts.picked;
  const int present = counts.bolls_present > 0 ? counts.bolls_present : counts.detected;
  if (present > 0) {
    metrics.action_success_pct = 100.0 * counts.picked / present;
    metrics.detection_performance_pct = 100.0 * counts.detected / present;
    metrics.reaching_ratio_pct = 100.0 * counts.reached / present;
  }
  return metrics;
}

std::string csvHeader() {
  return "run,bolls_present,detected,reached,picked,skipped,pick_attempts,time_s,distance_m,ov_cm_s,pr_bolls_s,"
         "ct_s,asr_pct,dp_pct,mrr_pct";
}

namespace {
std::string optional(const std::optional<double>& value) {
  if (!value) return "";
  std::ostringstream out;
  out << std::fixed << std::setprecision(2) << *value;
  return out.str();
}
}  // namespace

std::string csvRow(const std::string& run, const HarvestCounts& counts, const HarvestMetrics& metrics) {
  std::ostringstream out;
  out << run << ',' << counts.bolls_present << ',' << counts.detected << ',' << counts.reached << ',' << counts.picked
      << ',' << counts.skipped << ',' << counts.pick_attempts << ',' << std::fixed << std::setprecision(2)
      << counts.time_s << ',' << std::setprecision(3) << counts.distance_m << ',' << std::setprecision(2)
      << metrics.operation_velocity_cm_s << ',' << std::setprecision(4) << metrics.production_rate_bolls_s << ','
      << optional(metrics.cycle_time_s) << ',' << optional(metrics.action_success_pct) << ','
      << optional(metrics.detection_performance_pct) << ',' << optional(metrics.reaching_ratio_pct);
  return out.str();
}

bool appendCsv(const std::string& path, const std::string& run, const HarvestCounts& counts,
               const HarvestMetrics& metrics, std::string* error) {
  bool empty = true;
  {
    std::ifstream existing(path);
    empty = !existing.good() || existing.peek() == std::ifstream::traits_type::eof();
  }
  std::ofstream out(path, std::ios::app);
  if (!out) {
    if (error) *error = "cannot open " + path + " for appending";
    return false;
  }
  if (empty) out << csvHeader() << '\n';
  out << csvRow(run, counts, metrics) << '\n';
  if (!out) {
    if (error) *error = "cannot write " + path;
    return false;
  }
  return true;
}

}  // namespace control
}  // namespace cotton_harvester
