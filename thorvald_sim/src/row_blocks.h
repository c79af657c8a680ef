// Fixed blocks of image rows dealt to threads, shared by the camera's read-back and its depth image.
#pragma once

#include <algorithm>
#include <thread>
#include <vector>

namespace thorvald_sim {

/// Runs body(b) for b = 0 .. blocks - 1, the blocks dealt round-robin to `threads` threads (this one among them
/// when threads is 1).
template <class Body>
inline void forBlocks(int blocks, int threads, const Body& body) {
  threads = std::max(1, std::min(threads, blocks));
  if (threads == 1) {
    for (int b = 0; b < blocks; ++b) body(b);
    return;
  }
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t)
    workers.emplace_back([&, t]() {
      for (int b = t; b < blocks; b += threads) body(b);
    });
  for (auto& w : workers) w.join();
}

}  // namespace thorvald_sim
