// Runs the unit tests with the virtual bus in a private folder of their own, removed at the end, so that tests
// neither see nor leave anything in the user's bus folder.
#include <ftw.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace {
int removeEntry(const char* path, const struct stat*, int, struct FTW*) { return ::remove(path); }
}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  char folder[] = "/tmp/thorvald_can_test.XXXXXX";
  if (!::mkdtemp(folder)) {
    std::perror("mkdtemp");
    return 1;
  }
  ::setenv("THORVALD_VCAN_DIR", folder, 1);
  const int result = RUN_ALL_TESTS();
  ::nftw(folder, removeEntry, 16, FTW_DEPTH | FTW_PHYS);
  return result;
}
