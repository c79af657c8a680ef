// runNode as a node's main() runs it, in child processes under a rostest master: the exit code when the node
// cannot start, after an orderly shutdown and after SIGTERM.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_common/ros/run_node.h"

namespace {

/// Runs `main_body` in a child process (its return value is the child's exit code); `while_running` runs in the
/// parent meanwhile with the child's pid. Returns the child's exit code (-1 if it did not exit normally).
template <typename Body, typename Parent>
int exitCodeOf(Body main_body, Parent while_running) {
  const pid_t pid = fork();
  if (pid == 0) _exit(main_body());
  while_running(pid);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int runWith(const std::string& name, const thorvald_common::NodeFactory& start) {
  std::string arg0 = "run_node_test";
  std::vector<char*> argv = {arg0.data()};
  int argc = static_cast<int>(argv.size());
  return thorvald_common::runNode(argc, argv.data(), name, start);
}

/// A node that shuts roscpp down itself after `after_s` [s] of spinning.
struct ShortLivedNode {
  ShortLivedNode(ros::NodeHandle& nh, double after_s)
      : timer(nh.createWallTimer(
            ros::WallDuration(after_s), [](const ros::WallTimerEvent&) { ros::requestShutdown(); }, true)) {}
  ros::WallTimer timer;
};

}  // namespace

TEST(RunNode, ANodeThatCannotStartExitsOne) {
  const int code = exitCodeOf(
      [] {
        return runWith("bad_params", [](ros::NodeHandle&, ros::NodeHandle&) -> std::shared_ptr<void> {
          throw thorvald_common::ParamError("/bad_params: parameter ~rate: found the string 'fast', expected a number");
        });
      },
      [](pid_t) {});
  EXPECT_EQ(code, 1);
}

TEST(RunNode, AnyStartUpErrorExitsOne) {
  const int code = exitCodeOf(
      [] {
        return runWith("no_port", [](ros::NodeHandle&, ros::NodeHandle&) -> std::shared_ptr<void> {
          throw std::runtime_error("cannot open /dev/ttyNONE");
        });
      },
      [](pid_t) {});
  EXPECT_EQ(code, 1);
}

TEST(RunNode, AnOrderlyShutdownExitsZero) {
  const int code = exitCodeOf(
      [] {
        return runWith("short_lived",
                       [](ros::NodeHandle& nh, ros::NodeHandle&) { return std::make_shared<ShortLivedNode>(nh, 0.3); });
      },
      [](pid_t) {});
  EXPECT_EQ(code, 0);
}

TEST(RunNode, SigtermWhileSpinningExitsZeroWithinTheGrace) {
  const auto start = std::chrono::steady_clock::now();
  const int code = exitCodeOf(
      [] {
        return runWith("long_lived", [](ros::NodeHandle& nh, ros::NodeHandle&) {
          return std::make_shared<ShortLivedNode>(nh, 60.0);
        });
      },
      [](pid_t pid) {
        std::this_thread::sleep_for(std::chrono::seconds(2));  // the child is spinning by then
        kill(pid, SIGTERM);
      });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(code, 0);
  EXPECT_LT(seconds, 10.0);  // 2 s before the signal, then at most the 0.7 s grace; generous for a loaded machine
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
