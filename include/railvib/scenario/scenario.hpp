// railvib/scenario: a whole scenario checked at once, before anything runs.
//
// validateScenario() runs the loader of every section (the same loaders the nodes and tools use),
// the checks that need two sections (rates of the streams between the steps, sensor points, files
// that must exist and be valid), then refuses every key no loader asked for (a typo), with the
// nearest valid key. `railvib_tool config-check`, every railvib_tool command that takes --config,
// and every node call it, so a scenario is refused in one place, with the key, the value, the
// allowed range or reason, and the file.
#pragma once

#include <nlohmann/json.hpp>

#include "railvib/common/config.hpp"
#include "railvib/soil/soil_params.hpp"

namespace railvib::scenario {

/// Throws ConfigError. Returns a summary: the sections, the virtual sensors (name, source, point),
/// the stream rates.
nlohmann::json validateScenario(const Config& config);

/// The soil's virtual sensors that stand on the house's foundation, one sentence each: with
/// building.coupling two_way the foundation is part of the soil model, so a sensor inside the house's
/// plan records the foundation's motion (rigid, or the meshed box's), not the ground's (the free field there is the one_way
/// run, whose soil does not see the house). Empty without a house or with one_way. `receivers`: the
/// soil's receivers (soil::SoilParams::receivers), where the sensors' points are.
std::vector<std::string> soilSensorsOnTheFoundation(const ConfigNode& root,
                                                    const std::vector<soil::ReceiverSpec>& receivers);

}  // namespace railvib::scenario
