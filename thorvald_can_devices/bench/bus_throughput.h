#pragma once
// Frames per second the virtual bus carries from one process to another.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "thorvald_can_devices/virtual_can_bus.h"

namespace thorvald_can_devices {

struct ThroughputResult {
  double fps = 0;  ///< frames received per second by the other process
  long sent = 0, received = 0;
  double seconds = 0;
};

/// The parent sends `frames` frames as fast as it can in windows of `window` frames, waiting for the child's
/// acknowledgement of each window (so no frame is lost to a full queue); the child counts.
inline ThroughputResult measureThroughput(long frames, int window = 200) {
  const std::string name = "bench" + std::to_string(::getpid());
  VirtualCanBus parent(name);
  const pid_t child = ::fork();
  if (child == 0) {
    long got = 0;
    {
      VirtualCanBus bus(name);
      bus.send(makeFrame(0x7E0, {}));
      CanFrame f;
      while (got < frames) {
        if (!bus.receive(&f)) {
          if (!bus.waitReadable(2.0)) break;
          continue;
        }
        ++got;
        if (got % window == 0) bus.send(makeFrame(0x7E1, {}));
      }
    }
    ::_exit(got == frames ? 0 : 1);
  }
  CanFrame f;
  while (!(parent.receive(&f) && f.id == 0x7E0)) parent.waitReadable(0.01);
  const auto t0 = std::chrono::steady_clock::now();
  ThroughputResult r;
  long acked = 0;
  CanFrame out = makeFrame(0x181, {1, 2, 3, 4, 5, 6, 7, 8});
  while (r.sent < frames) {
    for (int i = 0; i < window && r.sent < frames; ++i, ++r.sent) {
      out.data[0] = static_cast<uint8_t>(r.sent);
      parent.send(out);
    }
    while (acked < r.sent / window) {
      if (parent.receive(&f)) {
        if (f.id == 0x7E1) ++acked;
      } else if (!parent.waitReadable(2.0)) {
        break;
      }
    }
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.received = (WIFEXITED(status) && WEXITSTATUS(status) == 0) ? frames : -1;
  r.fps = r.received > 0 ? r.received / r.seconds : 0.0;
  return r;
}

}  // namespace thorvald_can_devices
