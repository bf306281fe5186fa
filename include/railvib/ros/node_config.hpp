// railvib ROS layer: every node loads the same scenario configuration, named
// by the global parameters /railvib/config_file and /railvib/config_overrides
// (a list of "key.path=value" strings set by the launch file's arguments).
#pragma once

#include <ros/ros.h>

#include "railvib/common/config.hpp"

namespace railvib::ros_io {

/// Load the scenario config; throws ConfigError (the node logs it and exits non-zero).
Config loadNodeConfig(ros::NodeHandle& nh);

/// Run a node body, turning exceptions into a FATAL log line and exit code 1.
template <class Body>
int runNode(const char* name, Body&& body) {
  try {
    body();
    return 0;
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", name, e.what());
    return 1;
  }
}

}  // namespace railvib::ros_io
