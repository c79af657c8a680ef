#include "thorvald_gnss/gpsd_source.h"

#include <gps.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace thorvald_gnss {
namespace {

// fix_conversion.cpp uses gpsd's numbers without including gps.h.
static_assert(MODE_2D == 2 && MODE_3D == 3, "gpsd's mode numbers changed");
static_assert(STATUS_DGPS_FIX == 2 && STATUS_RTK_FIX == 3 && STATUS_RTK_FLT == 4, "gpsd's status numbers changed");

double seconds(const timespec_t& t) { return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec); }

}  // namespace

GpsdSource::GpsdSource() : data_(std::make_unique<gps_data_t>()) {}

GpsdSource::~GpsdSource() { close(); }

bool GpsdSource::open(const std::string& host, const std::string& port, std::string& why) {
  close();
  where_ = "gpsd at " + host + ":" + port;
  std::memset(data_.get(), 0, sizeof(gps_data_t));
  errno = 0;
  const int code = gps_open(host.c_str(), port.c_str(), data_.get());
  if (code != 0) {
    why = where_ + ": " + gps_errstr(errno) + " (is gpsd running?)";
    return false;
  }
  open_ = true;
  if (gps_stream(data_.get(), WATCH_ENABLE | WATCH_JSON, nullptr) != 0) {
    why = where_ + ": the watch request failed: " + gps_errstr(errno);
    close();
    return false;
  }
  return true;
}

void GpsdSource::close() {
  if (!open_) return;
  gps_stream(data_.get(), WATCH_DISABLE, nullptr);
  gps_close(data_.get());
  open_ = false;
}

GpsdSource::ReadResult GpsdSource::read(double timeout_s, GpsdFix& fix, GpsdGst& gst, std::string& why) {
  if (!open_) {
    why = where_ + ": not connected";
    return ReadResult::kError;
  }
  const int timeout_us = static_cast<int>(std::lround(std::max(0.0, timeout_s) * 1e6));
  if (!gps_waiting(data_.get(), timeout_us)) {
    if (errno != 0 && errno != EINTR && errno != EAGAIN) {
      why = where_ + ": " + std::strerror(errno);
      errno = 0;
      return ReadResult::kError;
    }
    return ReadResult::kNothing;
  }
  data_->set = 0;
  errno = 0;
  if (gps_read(data_.get(), nullptr, 0) < 0) {
    why = where_ + ": connection closed (" + (errno ? std::string(std::strerror(errno)) : "gpsd went away") + ")";
    return ReadResult::kError;
  }
  const gps_data_t& d = *data_;
  if (d.set & GST_SET) {
    gst.time_s = seconds(d.gst.utctime);
    gst.latitude_sigma_m = d.gst.lat_err_deviation;
    gst.longitude_sigma_m = d.gst.lon_err_deviation;
    gst.altitude_sigma_m = d.gst.alt_err_deviation;
    return ReadResult::kGst;
  }
  if (d.set & MODE_SET) {
    fix.mode = d.fix.mode;
    fix.status = d.fix.status;
    fix.time_s = (d.set & TIME_SET) ? seconds(d.fix.time) : kUnknown;
    fix.latitude_deg = d.fix.latitude;
    fix.longitude_deg = d.fix.longitude;
    fix.altitude_m = d.fix.altHAE;
    fix.epx_m = d.fix.epx;
    fix.epy_m = d.fix.epy;
    fix.epv_m = d.fix.epv;
    return ReadResult::kFix;
  }
  return ReadResult::kOther;
}

}  // namespace thorvald_gnss
