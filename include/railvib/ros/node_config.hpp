// railvib ROS layer: every node loads the same scenario configuration, named
// by the global parameter /railvib/config_file, with the launch arguments the
// launch file puts under /railvib/launch_arguments/<name> (one parameter per
// argument, each mapped to one config key by scenario::launchArgumentOverrides:
// an argument's value can never name another key), then validates the whole
// scenario (scenario::validateScenario).
#pragma once

#include <ros/ros.h>

#include <string>
#include <utility>
#include <vector>

#include "railvib/common/config.hpp"

namespace railvib::ros_io {

/// Load and validate the scenario config; throws ConfigError (the node logs it and exits non-zero).
Config loadNodeConfig(ros::NodeHandle& nh);

/// What produced this run, as YAML for the bag (names::kScenarioTopic): railvib version (git describe),
/// the command line (/railvib/command_line, set by the launch file from $RAILVIB_COMMAND_LINE), the
/// config file, the launch arguments and direct overrides, the host and wall time, and the resolved
/// configuration (after includes and overrides) under `config`.
std::string scenarioRecordYaml(ros::NodeHandle& nh, const Config& config);

/// The node cannot start: FATAL line, ERROR on /diagnostics (latched, given a moment to go out).
void reportStartFailure(const std::string& node, const std::string& message);

/// Run a node body, turning exceptions into a FATAL log line, ERROR on /diagnostics and exit code 1.
template <class Body>
int runNode(const char* name, Body&& body) {
  try {
    body();
    return 0;
  } catch (const std::exception& e) {
    reportStartFailure(name, e.what());
    return 1;
  }
}

}  // namespace railvib::ros_io
