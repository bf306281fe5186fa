// railvib_tool config-check: load a scenario and validate every section with
// the same loaders the nodes use; print the merged configuration on request.
#include "command_registry.hpp"
#include "railvib/building/model.hpp"
#include "railvib/common/site.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/vehicle_params.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

int configCheck(const std::vector<std::string>& args) {
  ArgParser parser("config-check", "Validate every section of a scenario configuration (exit 3 on the first error).");
  addConfigOptions(parser);
  parser.flag("dump", "print the merged configuration (YAML) instead of the summary");
  if (!parser.parse(args)) return 0;
  const Config config = loadConfig(parser);
  const ConfigNode root = config.root();
  const auto track = track::loadTrackParams(root);
  vehicle::loadVehicleParams(root);
  vehicle::loadUnevennessParams(root);
  vehicle::loadPassageParams(root);
  const building::BuildingParams house = building::loadBuildingParams(root);
  soil::loadSoilParams(root, {building::freeFieldPoints(house), {}});
  const SiteLayout site = loadSiteLayout(root);
  if (parser.isSet("dump")) {
    std::cout << config.dump() << std::endl;
    return 0;
  }
  nlohmann::json summary;
  summary["config"] = config.file();
  summary["valid"] = true;
  summary["sections"] = {"simulation", "vehicle", "unevenness", "track", "soil", "building", "site"};
  summary["ground_sensors"] = site.ground_sensors.size();
  summary["track_foundation"] = track::foundationName(track.foundation);
  printJson(summary);
  return 0;
}

const Registrar reg("config-check", "validate a scenario configuration (every section)", configCheck);

}  // namespace
}  // namespace railvib::tool
