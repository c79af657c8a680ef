#include "thorvald_gnss/fix_conversion.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace thorvald_gnss {
namespace {

// gpsd's status numbers (gps.h, API 9 and later); gpsd_source.cpp checks them against the header.
constexpr int kGpsdStatusDgps = 2;
constexpr int kGpsdStatusRtkFixed = 3;
constexpr int kGpsdStatusRtkFloat = 4;
constexpr int kGpsdMode2d = 2;
constexpr int kGpsdMode3d = 3;
constexpr double kTwoDVerticalFactor = 100.0;  // variance factor of a 2D fix's unknown height

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

void checkSigma(const char* name, const ModeSigma& s, std::vector<std::string>& problems) {
  for (const auto& [key, value] : {std::pair{"horizontal_m", s.horizontal_m}, std::pair{"vertical_m", s.vertical_m}}) {
    if (!positive(value)) {
      std::ostringstream text;
      text << name << "." << key << ": " << value << " is not > 0";
      problems.push_back(text.str());
    }
  }
}

std::array<double, 9> diagonal(double east_m, double north_m, double up_m) {
  return {east_m * east_m, 0.0, 0.0, 0.0, north_m * north_m, 0.0, 0.0, 0.0, up_m * up_m};
}

}  // namespace

const char* covarianceSourceName(CovarianceSource source) {
  switch (source) {
    case CovarianceSource::kGst:
      return "GST";
    case CovarianceSource::kGpsdErrors:
      return "gpsd epx/epy/epv";
    case CovarianceSource::kModeSigma:
      return "fix mode sigma";
    default:
      return "none";
  }
}

std::vector<std::string> ModeSigmas::validate() const {
  std::vector<std::string> problems;
  checkSigma("rtk_fixed", rtk_fixed, problems);
  checkSigma("rtk_float", rtk_float, problems);
  checkSigma("dgps", dgps, problems);
  checkSigma("single", single, problems);
  if (!(gst_max_age_s >= 0.0 && std::isfinite(gst_max_age_s))) {
    problems.push_back("gst_max_age_s: " + std::to_string(gst_max_age_s) + " is not >= 0");
  }
  return problems;
}

FixConverter::FixConverter(ModeSigmas sigmas) : sigmas_(sigmas) {
  const auto problems = sigmas_.validate();
  if (!problems.empty()) {
    std::string text = "FixConverter: ";
    for (size_t i = 0; i < problems.size(); ++i) text += (i ? "; " : "") + problems[i];
    throw std::invalid_argument(text);
  }
}

bool FixConverter::addGst(const GpsdGst& gst) {
  if (!std::isfinite(gst.time_s) || !positive(gst.latitude_sigma_m) || !positive(gst.longitude_sigma_m) ||
      !positive(gst.altitude_sigma_m)) {
    return false;
  }
  gst_ = gst;
  return true;
}

const ModeSigma& FixConverter::modeSigma(int gpsd_status) const {
  switch (gpsd_status) {
    case kGpsdStatusRtkFixed:
      return sigmas_.rtk_fixed;
    case kGpsdStatusRtkFloat:
      return sigmas_.rtk_float;
    case kGpsdStatusDgps:
      return sigmas_.dgps;
    default:
      return sigmas_.single;
  }
}

NavFix FixConverter::convert(const GpsdFix& fix) {
  NavFix out;
  out.gpsd_status = fix.status;
  out.time_s = fix.time_s;
  const bool same_time = fix.time_s == last_time_s_ || (std::isnan(fix.time_s) && std::isnan(last_time_s_));
  out.repeat = any_report_ && same_time && fix.mode == last_mode_;
  any_report_ = true;
  last_time_s_ = fix.time_s;
  last_mode_ = fix.mode;
  const bool has_fix = (fix.mode == kGpsdMode2d || fix.mode == kGpsdMode3d) && std::isfinite(fix.latitude_deg) &&
                       std::isfinite(fix.longitude_deg);
  const int status = has_fix ? fix.status : 0;
  if (status != last_status_) {
    last_status_ = status;
    status_since_s_ = fix.time_s;
  }
  if (!has_fix) return out;  // NO_FIX, covariance unknown, position NaN

  out.status = (fix.status == kGpsdStatusRtkFixed || fix.status == kGpsdStatusRtkFloat) ? FixStatus::kGbasFix
               : fix.status == kGpsdStatusDgps                                          ? FixStatus::kSbasFix
                                                                                        : FixStatus::kFix;
  out.latitude_deg = fix.latitude_deg;
  out.longitude_deg = fix.longitude_deg;
  const bool has_height = fix.mode == kGpsdMode3d && std::isfinite(fix.altitude_m);
  out.altitude_m = has_height ? fix.altitude_m : kUnknown;

  const double age_s = gst_ ? fix.time_s - gst_->time_s : kUnknown;
  const bool gst_current = gst_ && std::isfinite(age_s) && age_s <= sigmas_.gst_max_age_s &&
                           age_s >= -sigmas_.gst_max_age_s &&
                           !(std::isfinite(status_since_s_) && gst_->time_s < status_since_s_);
  const ModeSigma& mode = modeSigma(fix.status);
  const double unknown_up_m = mode.vertical_m * std::sqrt(kTwoDVerticalFactor);
  if (gst_current) {
    out.covariance =
        diagonal(gst_->longitude_sigma_m, gst_->latitude_sigma_m, has_height ? gst_->altitude_sigma_m : unknown_up_m);
    out.covariance_type = CovarianceType::kDiagonalKnown;
    out.covariance_source = CovarianceSource::kGst;
  } else if (positive(fix.epx_m) && positive(fix.epy_m) && positive(fix.epv_m)) {
    out.covariance = diagonal(fix.epx_m, fix.epy_m, has_height ? fix.epv_m : unknown_up_m);
    out.covariance_type = CovarianceType::kDiagonalKnown;
    out.covariance_source = CovarianceSource::kGpsdErrors;
  } else {
    out.covariance = diagonal(mode.horizontal_m, mode.horizontal_m, has_height ? mode.vertical_m : unknown_up_m);
    out.covariance_type = CovarianceType::kApproximated;
    out.covariance_source = CovarianceSource::kModeSigma;
  }
  return out;
}

}  // namespace thorvald_gnss
