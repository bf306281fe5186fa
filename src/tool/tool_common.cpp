#include "tool_common.hpp"

#include <cstdlib>

#ifndef RAILVIB_SOURCE_DIR
#define RAILVIB_SOURCE_DIR "."
#endif

namespace railvib::tool {

std::string defaultConfigPath() {
  if (const char* env = std::getenv("RAILVIB_CONFIG")) return env;
  return std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml";
}

void addConfigOptions(ArgParser& parser) {
  parser.option("config", "scenario YAML file", defaultConfigPath());
  parser.option("set", "override a config value, key.path=value (repeatable)");
}

Config loadConfig(const ArgParser& parser, const std::vector<std::string>& extra_overrides) {
  std::vector<std::string> overrides = parser.getAll("set");
  overrides.insert(overrides.end(), extra_overrides.begin(), extra_overrides.end());
  return Config::load(parser.get("config"), overrides);
}

}  // namespace railvib::tool
