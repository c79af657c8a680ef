#include "thorvald_can_devices/candump_log.h"

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

namespace thorvald_can_devices {
namespace {
int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}
double wallTimeS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
}  // namespace

std::string formatCandumpLine(double time_s, const std::string& interface_name, const CanFrame& frame) {
  const long long whole = static_cast<long long>(std::floor(time_s));
  long long micro = std::llround((time_s - static_cast<double>(whole)) * 1e6);
  long long sec = whole;
  if (micro >= 1000000) {
    micro -= 1000000;
    ++sec;
  }
  char buf[48];
  std::snprintf(buf, sizeof(buf), "(%010lld.%06lld) ", sec, micro);
  return buf + interface_name + " " + toString(frame);
}

bool parseCandumpLine(const std::string& line, double* time_s, std::string* interface_name, CanFrame* frame) {
  // (seconds.micro) iface id#data
  if (line.size() < 4 || line[0] != '(') return false;
  const size_t close = line.find(')');
  if (close == std::string::npos) return false;
  const std::string stamp = line.substr(1, close - 1);
  const size_t dot = stamp.find('.');
  if (dot == std::string::npos || dot == 0 || stamp.size() - dot - 1 != 6) return false;
  for (size_t i = 0; i < stamp.size(); ++i)
    if (i != dot && !std::isdigit(static_cast<unsigned char>(stamp[i]))) return false;
  if (dot > 12) return false;
  const double t = std::stod(stamp.substr(0, dot)) + std::stod(stamp.substr(dot + 1)) * 1e-6;
  size_t p = close + 1;
  if (p >= line.size() || line[p] != ' ') return false;
  ++p;
  const size_t space = line.find(' ', p);
  if (space == std::string::npos || space == p) return false;
  const std::string iface = line.substr(p, space - p);
  std::string rest = line.substr(space + 1);
  while (!rest.empty() && (rest.back() == '\n' || rest.back() == '\r' || rest.back() == ' ')) rest.pop_back();
  const size_t hash = rest.find('#');
  if (hash != 3 && hash != 8) return false;
  CanFrame f;
  uint32_t id = 0;
  for (size_t i = 0; i < hash; ++i) {
    const int v = hexValue(rest[i]);
    if (v < 0) return false;
    id = (id << 4) | static_cast<uint32_t>(v);
  }
  if (hash == 3) {
    if (id > kCanStdMask) return false;
  } else if (id > (kCanErrorFlag | kCanErrorMask)) {
    return false;  // flag bits other than the error flag are not written as part of the id
  } else if (!(id & kCanErrorFlag)) {
    id |= kCanEffFlag;
  }
  f.id = id;
  const std::string data = rest.substr(hash + 1);
  if (data == "R") {
    f.id |= kCanRtrFlag;
  } else {
    if (data.size() % 2 != 0 || data.size() > 16) return false;
    for (size_t i = 0; i < data.size(); i += 2) {
      const int hi = hexValue(data[i]), lo = hexValue(data[i + 1]);
      if (hi < 0 || lo < 0) return false;
      f.data[f.length++] = static_cast<uint8_t>(hi * 16 + lo);
    }
  }
  *time_s = t;
  *interface_name = iface;
  *frame = f;
  return true;
}

CandumpLogger::CandumpLogger(const std::string& path, std::string interface_name)
    : interface_(std::move(interface_name)) {
  file_ = std::fopen(path.c_str(), "a");
  if (!file_) throw CanBusError("cannot open CAN log '" + path + "': " + std::strerror(errno), errno);
}

CandumpLogger::~CandumpLogger() {
  if (file_) std::fclose(file_);
}

void CandumpLogger::write(const CanFrame& frame) {
  const std::string line = formatCandumpLine(wallTimeS(), interface_, frame) + "\n";
  std::fputs(line.c_str(), file_);
  std::fflush(file_);
  ++lines_;
}

LoggingCanBus::LoggingCanBus(std::unique_ptr<CanBus> inner, const std::string& path, const std::string& interface_name)
    : inner_(std::move(inner)), log_(path, interface_name) {}

bool LoggingCanBus::send(const CanFrame& frame) {
  const bool ok = inner_->send(frame);
  if (ok) log_.write(frame);
  return ok;
}

bool LoggingCanBus::receive(CanFrame* frame) {
  if (!inner_->receive(frame)) return false;
  log_.write(*frame);
  return true;
}

}  // namespace thorvald_can_devices
