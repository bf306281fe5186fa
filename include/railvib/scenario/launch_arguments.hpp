// railvib/scenario: the launch arguments the nodes map to config keys (speed:= ->
// simulation.speed_m_s, ...), one place for the nodes (ros/node_config) and railvib_tool
// config-check --arg, so a study can check a run's launch arguments before it starts.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace railvib::scenario {

/// Launch argument -> config key it overrides (speed:= -> simulation.speed_m_s, ...).
const std::vector<std::pair<std::string, std::string>>& launchArgumentKeys();

/// "key=value" overrides of the launch arguments (an empty value keeps the config's); throws
/// ConfigError for an argument that is not in launchArgumentKeys() or a value that is not one plain
/// value (a list or map).
std::vector<std::string> launchArgumentOverrides(const std::vector<std::pair<std::string, std::string>>& arguments);

}  // namespace railvib::scenario
