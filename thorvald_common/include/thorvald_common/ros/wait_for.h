#pragma once

#include <ros/init.h>
#include <ros/spinner.h>
#include <ros/time.h>

#include <type_traits>
#include <utility>

namespace thorvald_common {

/// Waits in a rostest gtest until `condition()` holds or `timeout_s` [s] of wall time pass, calling `step()`
/// between two checks (spin the callbacks, step a scripted robot, pump a bus). Stops early when roscpp shuts down.
/// Checks the condition once more at the deadline; returns whether it held. This is the tests' synchronisation:
/// a condition with a deadline, never a bare sleep.
template <typename Condition, typename Step, typename = std::enable_if_t<std::is_invocable_v<Step&>>>
bool waitFor(Condition&& condition, double timeout_s, Step&& step) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < deadline) {
    if (condition()) return true;
    step();
  }
  return condition();
}

/// A step that sleeps `poll_s` [s] and then runs this thread's pending callbacks (ros::spinOnce): for tests that
/// spin the global queue themselves.
inline auto spinEvery(double poll_s) {
  return [poll_s] {
    ros::WallDuration(poll_s).sleep();
    ros::spinOnce();
  };
}

/// A step that only sleeps `poll_s` [s]: for tests whose callbacks run in an AsyncSpinner.
inline auto sleepEvery(double poll_s) {
  return [poll_s] { ros::WallDuration(poll_s).sleep(); };
}

/// waitFor spinning this thread's callbacks every 5 ms.
template <typename Condition>
bool waitFor(Condition&& condition, double timeout_s) {
  return waitFor(std::forward<Condition>(condition), timeout_s, spinEvery(0.005));
}

}  // namespace thorvald_common
