// railvib_tool: helpers shared by subcommands.
#pragma once

#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "railvib/common/args.hpp"
#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"

namespace railvib::tool {

/// Default scenario file: $RAILVIB_CONFIG, else config/haren.yaml of the source tree.
std::string defaultConfigPath();

/// Declare the options every config-driven command takes: --config FILE and --set key=value.
void addConfigOptions(ArgParser& parser);
/// Parses a command whose first argument may name its case (`soil-bench lamb ...`) instead of its
/// --case option; `which` gets the case. Returns false after --help (nothing to run).
bool parseWithCase(ArgParser& parser, const std::vector<std::string>& args, std::string& which);

/// Load the configuration named by --config with the --set overrides, then
/// `extra_overrides` (a command's own options, e.g. --foundation) on top, and validate the whole
/// scenario (scenario::validateScenario: every section, cross-checks, unknown keys).
Config loadConfig(const ArgParser& parser, const std::vector<std::string>& extra_overrides = {});

/// A full-width track's column of one rail (a wheel's, a rail seat's) in the CSV files the tools write
/// and read: `base` + "_left" (y > 0, the building's side) or "_right".
inline std::string railColumn(const std::string& base, track::Rail rail) {
  return base + (rail == track::Rail::Left ? "_left" : "_right");
}

/// Print a JSON summary on stdout (indented).
inline void printJson(const nlohmann::json& summary) { std::cout << summary.dump(2) << std::endl; }

}  // namespace railvib::tool
