#pragma once

// The connection to gpsd through its client library (libgps: gps_open, gps_stream, gps_waiting, gps_read, gps_close),
// owned as a resource: it reads gpsd's JSON reports and hands over the fixes (TPV) and the receiver's error
// statistics (GST) as plain structs. ROS-free.

#include <memory>
#include <string>

#include "thorvald_gnss/fix_conversion.h"

struct gps_data_t;

namespace thorvald_gnss {

/// One connection to a gpsd daemon; closed when destroyed.
class GpsdSource {
 public:
  GpsdSource();
  ~GpsdSource();
  GpsdSource(const GpsdSource&) = delete;
  GpsdSource& operator=(const GpsdSource&) = delete;

  /// Connects to gpsd at `host`:`port` and asks it to stream JSON reports of every device. False with `why`
  /// ("gpsd at localhost:2947: connection refused") when it cannot.
  bool open(const std::string& host, const std::string& port, std::string& why);
  void close();
  bool isOpen() const { return open_; }

  enum class ReadResult { kNothing, kFix, kGst, kOther, kError };
  /// Waits up to `timeout_s` [s] for a report and reads one. kFix fills `fix`, kGst fills `gst`; kError: the
  /// connection broke (`why`), the caller closes and reconnects.
  ReadResult read(double timeout_s, GpsdFix& fix, GpsdGst& gst, std::string& why);

 private:
  std::unique_ptr<gps_data_t> data_;
  bool open_ = false;
  std::string where_;
};

}  // namespace thorvald_gnss
