#pragma once
// The harvest run's figures as a diagnostic_msgs/DiagnosticStatus (harvest/metrics), shared by the MuJoCo nodes.

#include <cstdio>
#include <string>

#include <diagnostic_msgs/DiagnosticStatus.h>

#include "cotton_harvester/control/harvest_metrics.h"

namespace cotton_harvester {
namespace sim {

/// Appends `key` with `value` printed to 3 decimals.
inline void addMetric(diagnostic_msgs::DiagnosticStatus* s, const std::string& key, double value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f", value);
  kv.value = text;
  s->values.push_back(kv);
}

/// Appends the counts and the paper's metrics of a run: bolls present and reachable, detected, reached, picked (by
/// the vacuum) and judged picked by the machine, time, OV, PR, CT, ASR, DP, MRR, the real-time factor and frames.
inline void addRunMetrics(diagnostic_msgs::DiagnosticStatus* s, const control::HarvestCounts& c,
                          const control::HarvestMetrics& m, int bolls_reachable, int machine_picked, double sim_s,
                          double wall_s, int frames) {
  addMetric(s, "bolls_present", c.bolls_present);
  addMetric(s, "bolls_reachable", bolls_reachable);
  addMetric(s, "detected", c.detected);
  addMetric(s, "reached", c.reached);
  addMetric(s, "picked", c.picked);
  addMetric(s, "machine_picked", machine_picked);
  addMetric(s, "time_s", c.time_s);
  addMetric(s, "ov_cm_s", m.operation_velocity_cm_s);
  addMetric(s, "pr_bolls_s", m.production_rate_bolls_s);
  addMetric(s, "ct_s", m.cycle_time_s.value_or(0.0));
  addMetric(s, "asr_pct", m.action_success_pct.value_or(0.0));
  addMetric(s, "dp_pct", m.detection_performance_pct.value_or(0.0));
  addMetric(s, "mrr_pct", m.reaching_ratio_pct.value_or(0.0));
  addMetric(s, "rtf", wall_s > 0.0 ? sim_s / wall_s : 0.0);
  addMetric(s, "frames", frames);
}

}  // namespace sim
}  // namespace cotton_harvester
