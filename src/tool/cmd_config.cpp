// railvib_tool config-check: load a scenario and validate every section with
// the same loaders the nodes use (scenario::validateScenario: every section,
// the checks between sections, unknown keys), with the launch arguments a launch would give the
// nodes (--arg) and any overrides (--set); print the merged configuration on request.
#include "command_registry.hpp"
#include "railvib/scenario/launch_arguments.hpp"
#include "railvib/scenario/scenario.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

int configCheck(const std::vector<std::string>& args) {
  ArgParser parser("config-check", "Validate every section of a scenario configuration (exit 3 on an error).");
  addConfigOptions(parser);
  parser.option("arg",
                "a launch argument NAME:=VALUE mapped to its config key as the nodes map it (speed:=5 is "
                "simulation.speed_m_s=5), applied before the --set overrides as in a launch (repeatable)");
  parser.flag("dump", "print the merged configuration (YAML) instead of the summary");
  if (!parser.parse(args)) return 0;
  std::vector<std::pair<std::string, std::string>> arguments;
  for (const std::string& a : parser.getAll("arg")) {
    const auto sep = a.find(":=");
    if (sep == std::string::npos || sep == 0) {
      throw ConfigError("config error: --arg " + a + ": expected NAME:=VALUE (a launch argument, e.g. speed:=8.33)");
    }
    arguments.emplace_back(a.substr(0, sep), a.substr(sep + 2));
  }
  std::vector<std::string> overrides = scenario::launchArgumentOverrides(arguments);
  for (const std::string& o : parser.getAll("set")) overrides.push_back(o);
  const Config config = Config::load(parser.get("config"), overrides);
  const nlohmann::json summary = scenario::validateScenario(config);
  if (parser.isSet("dump")) {
    std::cout << config.dump() << std::endl;
    return 0;
  }
  printJson(summary);
  return 0;
}

const Registrar reg("config-check", "validate a scenario configuration (every section, unknown keys)", configCheck);

}  // namespace
}  // namespace railvib::tool
