#pragma once

// The workspace's one command-line convention, for every program that takes options (benchmarks, tools, nodes):
// `--help` prints the usage on stdout and the program exits 0; a usage error (an unknown option, a missing or bad
// value) prints CLI11's message and a pointer to --help on stderr and the program exits 2, as POSIX utilities do.
// ROS-free: CLI11 only.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace thorvald_common {

/// Exit code of a program after a usage error.
constexpr int kUsageErrorExitCode = 2;

/// Prints what `error` calls for and returns the exit code of the convention: 0 after --help (or --help-all),
/// kUsageErrorExitCode after any usage error.
inline int commandLineExitCode(const CLI::App& app, const CLI::ParseError& error) {
  if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
    // --help, --help-all: the usage on stdout.
    if (dynamic_cast<const CLI::CallForAllHelp*>(&error)) {
      std::cout << app.help("", CLI::AppFormatMode::All) << std::flush;
    } else if (dynamic_cast<const CLI::CallForHelp*>(&error)) {
      std::cout << app.help() << std::flush;
    } else {
      std::cout << error.what() << std::endl;  // e.g. a version flag's text
    }
    return 0;
  }
  const std::string name = app.get_name().empty() ? std::string("error") : app.get_name();
  std::cerr << name << ": " << error.what() << "\nRun with --help for more information." << std::endl;
  return kUsageErrorExitCode;
}

/// Parses `argc`/`argv` into `app`. Returns nothing when the program goes on, or the code main() returns at once:
/// `if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;`
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return commandLineExitCode(app, e);
  }
  return std::nullopt;
}

/// The same for words already split off the command line (e.g. after removing roslaunch's own arguments), in
/// their order on the command line.
inline std::optional<int> parseCommandLine(CLI::App& app, std::vector<std::string> words) {
  try {
    std::reverse(words.begin(), words.end());  // CLI11 takes a vector last-first
    app.parse(words);
  } catch (const CLI::ParseError& e) {
    return commandLineExitCode(app, e);
  }
  return std::nullopt;
}

}  // namespace thorvald_common
