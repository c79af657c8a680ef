#pragma once

// The gpsd client's decisions about its connection: when to (re)connect, when gpsd counts as lost, and what the
// diagnostics say. ROS-free and clock-free: every call takes the time [s, any monotonic clock].

#include <string>
#include <vector>

namespace thorvald_gnss {

/// Timing of the connection to gpsd.
struct GpsdLinkParams {
  double timeout_s = 2.0;         ///< no report from gpsd for this long: "gpsd lost", reconnect [s]
  double retry_interval_s = 1.0;  ///< between two connection attempts [s]

  /// Problems, empty when usable.
  std::vector<std::string> validate() const;
};

/// Diagnostic level (the numbers of diagnostic_msgs/DiagnosticStatus).
enum class LinkLevel { kOk = 0, kWarn = 1, kError = 2 };

/// What the diagnostics report.
struct LinkHealth {
  LinkLevel level = LinkLevel::kError;
  std::string message;
};

/// State of the connection to gpsd and of the fixes coming through it.
class GpsdLink {
 public:
  /// Throws std::invalid_argument naming the problems of `params`.
  explicit GpsdLink(GpsdLinkParams params);

  /// Whether to try connecting now: not connected, and the retry interval since the last attempt has passed.
  bool shouldConnect(double now_s) const;
  /// The connection is up (gps_open and gps_stream succeeded).
  void connected(double now_s);
  /// A connection attempt failed with `why`.
  void connectFailed(double now_s, const std::string& why);
  /// The connection broke (read error, gpsd closed it) with `why`.
  void disconnected(double now_s, const std::string& why);

  /// gpsd sent a fix report; `has_fix` when its mode is 2D or 3D. `what` names the fix ("RTK fixed").
  void report(double now_s, bool has_fix, const std::string& what);
  /// Connected, but nothing from gpsd for timeout_s: the caller drops the connection and calls disconnected().
  bool timedOut(double now_s) const;

  bool isConnected() const { return connected_; }
  LinkHealth health(double now_s) const;

  unsigned long connections() const { return connections_; }
  unsigned long failedAttempts() const { return failed_attempts_; }
  unsigned long reports() const { return reports_; }
  unsigned long fixes() const { return fixes_; }
  const std::string& lastError() const { return last_error_; }

 private:
  GpsdLinkParams params_;
  bool connected_ = false;
  bool attempted_ = false;
  double last_attempt_s_ = 0.0;
  double connected_since_s_ = 0.0;
  bool any_report_ = false;  ///< since the current connection
  double last_report_s_ = 0.0;
  bool any_fix_ = false;  ///< since the current connection
  double last_fix_s_ = 0.0;
  std::string last_fix_what_;
  std::string last_error_;
  unsigned long connections_ = 0;
  unsigned long failed_attempts_ = 0;
  unsigned long reports_ = 0;
  unsigned long fixes_ = 0;
};

}  // namespace thorvald_gnss
