#include "thorvald_gnss/nmea_log.h"

namespace thorvald_gnss {
namespace {

/// The UTC field of a GGA, RMC or GST sentence ("$GNGGA,hhmmss.ss,..."), empty for other sentences.
std::string timeField(const std::string& sentence) {
  if (sentence.size() < 8) return "";
  const std::string type = sentence.substr(3, 3);
  if (type != "GGA" && type != "RMC" && type != "GST") return "";
  const size_t start = sentence.find(',');
  const size_t end = sentence.find(',', start + 1);
  if (start == std::string::npos || end == std::string::npos) return "";
  return sentence.substr(start + 1, end - start - 1);
}

}  // namespace

std::vector<NmeaEpoch> readNmeaEpochs(std::istream& in, size_t* rejected, size_t max_lines) {
  std::vector<NmeaEpoch> epochs;
  size_t bad = 0;
  std::string line;
  for (size_t n = 0; n < max_lines && std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (line[0] != '$') {
      ++bad;
      continue;
    }
    const std::string time = timeField(line);
    if (epochs.empty() || (!time.empty() && time != epochs.back().time && !epochs.back().time.empty())) {
      epochs.push_back({time, ""});
    } else if (epochs.back().time.empty()) {
      epochs.back().time = time;
    }
    epochs.back().text += line + "\r\n";
  }
  if (rejected) *rejected = bad;
  return epochs;
}

}  // namespace thorvald_gnss
