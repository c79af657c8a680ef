// Replays the fuzz corpus kept in the repository through every decoder with the normal compiler, so that each
// test run (also under the sanitizers in CI) covers the inputs libFuzzer found interesting.
#include <gtest/gtest.h>

#include <dirent.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../fuzz/decoders.h"

namespace {

std::vector<std::string> corpusFiles(const std::string& target) {
  std::vector<std::string> out;
  const std::string dir = "fuzz/corpus/" + target;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d))
      if (e->d_name[0] != '.') out.push_back(dir + "/" + e->d_name);
    closedir(d);
  }
  return out;
}

size_t replay(const std::string& target, void (*fn)(const uint8_t*, size_t)) {
  const auto files = corpusFiles(target);
  for (const auto& path : files) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    fn(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  }
  return files.size();
}

TEST(Corpus, ThorvaldFrames) { EXPECT_GE(replay("thorvald_frames", thorvald_can_devices::fuzzThorvaldFrames), 10u); }
TEST(Corpus, BatteryFrames) { EXPECT_GE(replay("battery_frames", thorvald_can_devices::fuzzBatteryFrames), 5u); }
TEST(Corpus, CanopenFrames) { EXPECT_GE(replay("canopen_frames", thorvald_can_devices::fuzzCanopenFrames), 10u); }
TEST(Corpus, CandumpLine) { EXPECT_GE(replay("candump_line", thorvald_can_devices::fuzzCandumpLine), 5u); }

}  // namespace
