// railvib/io: the scenario record, the YAML text that says what produced a run (the bag's
// names::kScenarioTopic). Every text field is written double-quoted: a reader then gets it back as
// text whatever it looks like (a git describe such as 8080946, a digits-only host name, a time that
// a YAML 1.1 reader would turn into a timestamp, a launch argument "2").
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "railvib/common/config.hpp"

namespace railvib::io {

struct ScenarioRecordFields {
  std::string railvib_version;                                        ///< git describe of the build
  std::string command_line;                                           ///< how the run was started
  std::string config_file;                                            ///< the scenario file as given
  std::vector<std::pair<std::string, std::string>> launch_arguments;  ///< name, value as typed
  std::vector<std::string> config_overrides;                          ///< "key.path=value"
  std::string host;
  std::string recorded_utc;  ///< ISO 8601, e.g. 2026-12-05T07:21:01Z
};

/// The record: the fields above, then the resolved configuration (after includes and overrides)
/// under `config`.
std::string scenarioRecordYaml(const ScenarioRecordFields& fields, const Config& config);

}  // namespace railvib::io
