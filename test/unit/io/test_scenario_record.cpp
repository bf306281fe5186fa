// The scenario record reads back as it was written: text stays text whatever it looks like.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "railvib/io/scenario_record.hpp"

namespace railvib::io {
namespace {

// A plain (unquoted) scalar is typed by its look in YAML (1.1 and 1.2 core schema: 8080946 is an
// int, 2026-12-05T07:21:01Z a timestamp in 1.1, true a bool, ~ null); yaml-cpp tags a quoted
// scalar "!" (non-specific, always a string) and a plain one "?".
void expectText(const YAML::Node& node, const std::string& value, const std::string& what) {
  ASSERT_TRUE(node.IsScalar()) << what;
  EXPECT_EQ(node.Tag(), "!") << what << " is written plain: a YAML reader may type it";
  EXPECT_EQ(node.as<std::string>(), value) << what;
}

TEST(ScenarioRecord, TextFieldsReadBackAsTextWhateverTheyLookLike) {
  ScenarioRecordFields fields;
  fields.railvib_version = "8080946";  // a git describe that is all digits (a CI run failed on it)
  fields.command_line = "true";
  fields.config_file = "~";
  fields.launch_arguments = {{"ranks", "2"}, {"speed", "1e1"}, {"width", "null"}};
  fields.config_overrides = {"simulation.duration_s=0.5", "0x10"};
  fields.host = "1234";
  fields.recorded_utc = "2026-12-05T07:21:01Z";
  const Config config = Config::fromString("simulation:\n  duration_s: 0.5\n  name: haren\n");

  const YAML::Node record = YAML::Load(scenarioRecordYaml(fields, config));
  expectText(record["railvib_version"], "8080946", "railvib_version");
  expectText(record["command_line"], "true", "command_line");
  expectText(record["config_file"], "~", "config_file");
  ASSERT_EQ(record["launch_arguments"].size(), 3u);
  expectText(record["launch_arguments"]["ranks"], "2", "launch_arguments.ranks");
  expectText(record["launch_arguments"]["speed"], "1e1", "launch_arguments.speed");
  expectText(record["launch_arguments"]["width"], "null", "launch_arguments.width");
  ASSERT_EQ(record["config_overrides"].size(), 2u);
  expectText(record["config_overrides"][0], "simulation.duration_s=0.5", "config_overrides[0]");
  expectText(record["config_overrides"][1], "0x10", "config_overrides[1]");
  expectText(record["host"], "1234", "host");
  expectText(record["recorded_utc"], "2026-12-05T07:21:01Z", "recorded_utc");
  // The configuration keeps its values: a number is still a number.
  EXPECT_DOUBLE_EQ(record["config"]["simulation"]["duration_s"].as<double>(), 0.5);
  EXPECT_EQ(record["config"]["simulation"]["name"].as<std::string>(), "haren");
}

}  // namespace
}  // namespace railvib::io
