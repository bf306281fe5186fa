#include "tool_common.hpp"

#include <cstdlib>

#include "railvib/scenario/scenario.hpp"

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
  parser.option("set", "override a config value, key.path=value or key.list[INDEX].key=value (repeatable)");
}

bool parseWithCase(ArgParser& parser, const std::vector<std::string>& args, std::string& which) {
  std::vector<std::string> rest = args;
  which.clear();
  if (!rest.empty() && rest[0].rfind("--", 0) != 0) {
    which = rest[0];
    rest.erase(rest.begin());
  }
  if (!parser.parse(rest)) return false;
  if (which.empty()) which = parser.get("case");
  return true;
}

Config loadConfig(const ArgParser& parser, const std::vector<std::string>& extra_overrides) {
  std::vector<std::string> overrides = parser.getAll("set");
  overrides.insert(overrides.end(), extra_overrides.begin(), extra_overrides.end());
  Config config = Config::load(parser.get("config"), overrides);
  // The whole scenario, as config-check sees it: a typo in --set or in any file is refused here.
  scenario::validateScenario(config);
  return config;
}

}  // namespace railvib::tool
