// The workspace's command-line convention: --help exits 0, a usage error exits 2 (thorvald_common/command_line.h),
// checked on the helper and on programs built with it.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "thorvald_common/command_line.h"

namespace thorvald_common {
namespace {

/// Parses `words` (after the program name) into an app with one integer option `--count` in [1, 10].
std::optional<int> parse(std::vector<std::string> words, int* count) {
  CLI::App app("a test program", "test_program");
  app.add_option("--count", *count, "a number")->check(CLI::Range(1, 10));
  words.insert(words.begin(), "test_program");
  std::vector<const char*> argv;
  for (const auto& w : words) argv.push_back(w.c_str());
  return parseCommandLine(app, static_cast<int>(argv.size()), argv.data());
}

TEST(CommandLine, GoodOptionsGoOn) {
  int count = 0;
  EXPECT_EQ(parse({"--count", "3"}, &count), std::nullopt);
  EXPECT_EQ(count, 3);
  EXPECT_EQ(parse({}, &count), std::nullopt);
}

TEST(CommandLine, HelpExitsZero) {
  int count = 0;
  EXPECT_EQ(parse({"--help"}, &count), std::optional<int>(0));
  EXPECT_EQ(parse({"-h"}, &count), std::optional<int>(0));
}

TEST(CommandLine, UsageErrorsExitTwo) {
  int count = 0;
  EXPECT_EQ(parse({"--no-such-option"}, &count), std::optional<int>(kUsageErrorExitCode));
  EXPECT_EQ(parse({"--count"}, &count), std::optional<int>(kUsageErrorExitCode));        // value missing
  EXPECT_EQ(parse({"--count", "x"}, &count), std::optional<int>(kUsageErrorExitCode));   // not a number
  EXPECT_EQ(parse({"--count", "99"}, &count), std::optional<int>(kUsageErrorExitCode));  // out of range
  EXPECT_EQ(parse({"stray"}, &count), std::optional<int>(kUsageErrorExitCode));          // extra word
  EXPECT_EQ(kUsageErrorExitCode, 2);
}

TEST(CommandLine, WordsInCommandLineOrder) {
  CLI::App app("a test program", "test_program");
  std::string first, second;
  app.add_option("--first", first);
  app.add_option("--second", second);
  EXPECT_EQ(parseCommandLine(app, {"--first", "a", "--second", "b"}), std::nullopt);
  EXPECT_EQ(first, "a");
  EXPECT_EQ(second, "b");
  EXPECT_EQ(parseCommandLine(app, {"--third"}), std::optional<int>(kUsageErrorExitCode));
}

/// Exit code of `program` run with `arguments` (output discarded); -1 when it did not exit normally.
int exitCode(const std::string& program, const std::string& arguments) {
  const int status = std::system((program + " " + arguments + " >/dev/null 2>&1").c_str());
  return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(CommandLine, ProgramsFollowTheConvention) {
  for (const std::string program : {CYCLE_BENCH, ODOMETRY_BENCH}) {
    SCOPED_TRACE(program);
    EXPECT_EQ(exitCode(program, "--help"), 0);
    EXPECT_EQ(exitCode(program, "--no-such-option"), 2);
    EXPECT_EQ(exitCode(program, "stray-word"), 2);
  }
  EXPECT_EQ(exitCode(CYCLE_BENCH, "--cycles not-a-number"), 2);
  EXPECT_EQ(exitCode(CYCLE_BENCH, "--cycles 0"), 2);  // outside [1, 1e8]
  EXPECT_EQ(exitCode(ODOMETRY_BENCH, "--seeds"), 2);  // value missing
}

}  // namespace
}  // namespace thorvald_common
