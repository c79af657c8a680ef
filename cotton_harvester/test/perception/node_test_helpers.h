#pragma once

#include <functional>
#include <string>

#include <ros/ros.h>
#include <thorvald_common/ros/wait_for.h>

#include "../cloud_message.h"

namespace cotton_harvester {
namespace test {

using thorvald_common::waitFor;  // spins until the condition holds or the deadline [s] passes

}  // namespace test
}  // namespace cotton_harvester
