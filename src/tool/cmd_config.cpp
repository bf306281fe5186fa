// railvib_tool config-check: load a scenario and validate every section with
// the same loaders the nodes use (scenario::validateScenario: every section,
// the checks between sections, unknown keys); print the merged configuration on request.
#include "command_registry.hpp"
#include "railvib/scenario/scenario.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

int configCheck(const std::vector<std::string>& args) {
  ArgParser parser("config-check", "Validate every section of a scenario configuration (exit 3 on an error).");
  addConfigOptions(parser);
  parser.flag("dump", "print the merged configuration (YAML) instead of the summary");
  if (!parser.parse(args)) return 0;
  const Config config = Config::load(parser.get("config"), parser.getAll("set"));
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
