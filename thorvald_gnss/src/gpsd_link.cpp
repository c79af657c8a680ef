#include "thorvald_gnss/gpsd_link.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace thorvald_gnss {
namespace {

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f s", s);
  return text;
}

}  // namespace

std::vector<std::string> GpsdLinkParams::validate() const {
  std::vector<std::string> problems;
  if (!(timeout_s > 0.0 && std::isfinite(timeout_s))) {
    problems.push_back("timeout: " + std::to_string(timeout_s) + " is not > 0");
  }
  if (!(retry_interval_s > 0.0 && std::isfinite(retry_interval_s))) {
    problems.push_back("retry_interval: " + std::to_string(retry_interval_s) + " is not > 0");
  }
  return problems;
}

GpsdLink::GpsdLink(GpsdLinkParams params) : params_(params) {
  const auto problems = params_.validate();
  if (!problems.empty()) {
    std::string text = "GpsdLink: ";
    for (size_t i = 0; i < problems.size(); ++i) text += (i ? "; " : "") + problems[i];
    throw std::invalid_argument(text);
  }
}

bool GpsdLink::shouldConnect(double now_s) const {
  return !connected_ && (!attempted_ || now_s - last_attempt_s_ >= params_.retry_interval_s);
}

void GpsdLink::connected(double now_s) {
  connected_ = true;
  attempted_ = true;
  last_attempt_s_ = now_s;
  connected_since_s_ = now_s;
  any_report_ = false;
  any_fix_ = false;
  ++connections_;
}

void GpsdLink::connectFailed(double now_s, const std::string& why) {
  connected_ = false;
  attempted_ = true;
  last_attempt_s_ = now_s;
  last_error_ = why;
  ++failed_attempts_;
}

void GpsdLink::disconnected(double now_s, const std::string& why) {
  connected_ = false;
  attempted_ = true;
  last_attempt_s_ = now_s;  // the next attempt waits a retry interval: gpsd may be restarting
  last_error_ = why;
}

void GpsdLink::report(double now_s, bool has_fix, const std::string& what) {
  any_report_ = true;
  last_report_s_ = now_s;
  ++reports_;
  if (has_fix) {
    any_fix_ = true;
    last_fix_s_ = now_s;
    last_fix_what_ = what;
    ++fixes_;
  }
}

bool GpsdLink::timedOut(double now_s) const {
  if (!connected_) return false;
  const double since = any_report_ ? last_report_s_ : connected_since_s_;
  return now_s - since > params_.timeout_s;
}

LinkHealth GpsdLink::health(double now_s) const {
  if (!connected_) {
    return {LinkLevel::kError, "gpsd lost: " + (last_error_.empty() ? std::string("not connected") : last_error_) +
                                   "; retrying every " + seconds(params_.retry_interval_s)};
  }
  if (!any_report_ || now_s - last_report_s_ > params_.timeout_s) {
    const double since = any_report_ ? last_report_s_ : connected_since_s_;
    return {LinkLevel::kError, "no fix: no report from gpsd for " + seconds(now_s - since) + " (receiver silent?)"};
  }
  if (!any_fix_ || now_s - last_fix_s_ > params_.timeout_s) {
    const double since = any_fix_ ? last_fix_s_ : connected_since_s_;
    return {LinkLevel::kWarn, "no fix for " + seconds(now_s - since) + " (gpsd reports no position)"};
  }
  return {LinkLevel::kOk, last_fix_what_};
}

}  // namespace thorvald_gnss
