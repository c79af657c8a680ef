#include "thorvald_base/can_relay.h"

#include <algorithm>
#include <utility>

#include "thorvald_base/robot_config.h"

namespace thorvald_base {

CanRelay::CanRelay(BaseHardware& hardware, std::set<uint32_t> allowed, CanRelayOptions options)
    : hardware_(hardware), allowed_(std::move(allowed)), options_(options) {
  if (options_.max_sent_per_cycle < 1) {
    throw ConfigError("base_driver", "~relay_max_frames_per_cycle",
                      "is " + std::to_string(options_.max_sent_per_cycle) + ", expected at least 1");
  }
  if (options_.max_received_per_cycle < 1) {
    throw ConfigError("base_driver", "~relay_max_received_per_cycle",
                      "is " + std::to_string(options_.max_received_per_cycle) + ", expected at least 1");
  }
}

RelayVerdict CanRelay::offer(const std::string& sender, const CanFrameData& frame) {
  RelayVerdict verdict;
  if (muted_) {
    ++counters_.dropped;
    verdict.kind = RelayVerdict::Kind::kMuted;
    return verdict;
  }
  if (sent_this_cycle_ >= options_.max_sent_per_cycle) {
    ++counters_.dropped;
    verdict.kind = RelayVerdict::Kind::kOverCycleBound;
    return verdict;
  }
  if (!allowed_.count(frame.id)) {
    return refuse(sender, "id not in the allow-list (implement_can_ids or ~relay_allowed_ids)");
  }
  std::string why;
  if (!hardware_.sendRelayFrame(frame, &why)) return refuse(sender, why);
  ++counters_.sent;
  ++sent_this_cycle_;
  return verdict;
}

RelayVerdict CanRelay::refuse(const std::string& sender, std::string why) {
  ++counters_.refused;
  auto& by = counters_.refused_by;
  auto it = by.find(sender);
  if (it == by.end()) {
    // Bounded: past kMaxSenders callers, the rest are counted together.
    it = by.size() < kMaxSenders ? by.emplace(sender, 0).first : by.emplace("(other senders)", 0).first;
  }
  ++it->second;
  RelayVerdict verdict;
  verdict.kind = RelayVerdict::Kind::kRefused;
  verdict.why = std::move(why);
  verdict.refused_from_sender = it->second;
  return verdict;
}

std::vector<CanFrameData> CanRelay::cycle() {
  // Bounded like the bus reads: a flood of implement frames cannot stretch the cycle with publishing.
  std::vector<CanFrameData> frames = hardware_.takeRelayFrames();
  const size_t n = std::min(frames.size(), static_cast<size_t>(options_.max_received_per_cycle));
  counters_.received_dropped += frames.size() - n;
  counters_.received += n;
  frames.resize(n);
  sent_this_cycle_ = 0;
  return frames;
}

}  // namespace thorvald_base
