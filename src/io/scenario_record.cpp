#include "railvib/io/scenario_record.hpp"

#include <yaml-cpp/yaml.h>

namespace railvib::io {

std::string scenarioRecordYaml(const ScenarioRecordFields& fields, const Config& config) {
  YAML::Emitter out;
  // Plain scalars are typed by their look (8080946 would read back as an integer): quote all text.
  const auto text = [&out](const std::string& value) { out << YAML::DoubleQuoted << value; };
  out << YAML::BeginMap;
  out << YAML::Key << "railvib_version" << YAML::Value;
  text(fields.railvib_version);
  out << YAML::Key << "command_line" << YAML::Value;
  text(fields.command_line);
  out << YAML::Key << "config_file" << YAML::Value;
  text(fields.config_file);
  out << YAML::Key << "launch_arguments" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, value] : fields.launch_arguments) {
    out << YAML::Key << name << YAML::Value;
    text(value);
  }
  out << YAML::EndMap;
  out << YAML::Key << "config_overrides" << YAML::Value << YAML::BeginSeq;
  for (const auto& o : fields.config_overrides) text(o);
  out << YAML::EndSeq;
  out << YAML::Key << "host" << YAML::Value;
  text(fields.host);
  out << YAML::Key << "recorded_utc" << YAML::Value;
  text(fields.recorded_utc);
  out << YAML::Key << "config" << YAML::Value << YAML::Load(config.dump());
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace railvib::io
