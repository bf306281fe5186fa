#include "railvib/scenario/launch_arguments.hpp"

#include <algorithm>

#include "railvib/common/config.hpp"

namespace railvib::scenario {

const std::vector<std::pair<std::string, std::string>>& launchArgumentKeys() {
  static const std::vector<std::pair<std::string, std::string>> keys{{"speed", "simulation.speed_m_s"},
                                                                     {"duration", "simulation.duration_s"},
                                                                     {"foundation", "track.foundation.model"},
                                                                     {"track", "simulation.vehicle_track"},
                                                                     {"coupling", "building.coupling"},
                                                                     {"vehicle", "vehicle.name"},
                                                                     {"width", "track.width"},
                                                                     {"defect_rails", "unevenness.defect.rails"}};
  return keys;
}

std::vector<std::string> launchArgumentOverrides(const std::vector<std::pair<std::string, std::string>>& arguments) {
  std::vector<std::string> overrides;
  for (const auto& [name, value] : arguments) {
    const auto& keys = launchArgumentKeys();
    const auto it = std::find_if(keys.begin(), keys.end(), [&](const auto& k) { return k.first == name; });
    if (it == keys.end()) {
      std::string known;
      for (const auto& k : keys) known += (known.empty() ? "" : ", ") + k.first;
      throw ConfigError("config error: launch argument " + name + " is not one the nodes know (" + known + ")");
    }
    if (value.empty()) continue;  // left empty: the config's value stays
    // One plain value: YAML flow collections, documents or several lines would be more than one value.
    if (value.find_first_of("[]{}\n\r") != std::string::npos || value.find(": ") != std::string::npos ||
        value.find(", ") != std::string::npos || value.find('"') != std::string::npos) {
      throw ConfigError("config error: " + it->second + " = " + value + ": launch argument " + name +
                        ":= must be one plain value [launch argument " + name + "]");
    }
    overrides.push_back(it->second + "=" + value);
  }
  return overrides;
}

}  // namespace railvib::scenario
