// The one header of names and its Python mirror (scripts/railvib_names.py).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "railvib/common/names.hpp"

namespace names = railvib::names;

namespace {
// NAME = "value" assignments of the Python module.
std::map<std::string, std::string> pythonConstants() {
  std::ifstream in(std::string(RAILVIB_SOURCE_DIR) + "/scripts/railvib_names.py");
  std::stringstream text;
  text << in.rdbuf();
  std::map<std::string, std::string> out;
  const std::string s = text.str();
  const std::regex assignment(R"(^([A-Z_]+) = \"([^\"]*)\")", std::regex::multiline);
  for (auto it = std::sregex_iterator(s.begin(), s.end(), assignment); it != std::sregex_iterator(); ++it) {
    out[(*it)[1]] = (*it)[2];
  }
  return out;
}
}  // namespace

TEST(Names, PythonMirrorAgrees) {
  const auto py = pythonConstants();
  const std::map<std::string, std::string> expected = {
      {"TRACK_FRAME", names::kTrackFrame},
      {"BUILDING_FRAME", names::kBuildingFrame},
      {"CONTACT_FORCES", std::string("/") + names::kContactForcesTopic},
      {"SOIL_LOADS", std::string("/") + names::kSoilLoadsTopic},
      {"SURFACE_VELOCITIES", std::string("/") + names::kSurfaceVelocitiesTopic},
      {"BUILDING_RESPONSE", std::string("/") + names::kBuildingResponseTopic},
      {"SENSOR_SAMPLES", std::string("/") + names::kSensorSamplesTopic},
      {"SLEEPER_LAYOUT", std::string("/") + names::kSleeperLayoutTopic},
      {"SURFACE_POINTS", std::string("/") + names::kSurfacePointsTopic},
      {"BUILDING_POINTS", std::string("/") + names::kBuildingPointsTopic},
      {"SURFACE_SNAPSHOT", std::string("/") + names::kSurfaceSnapshotTopic},
      {"SECTION_SNAPSHOT", std::string("/") + names::kSectionSnapshotTopic},
      {"SENSOR_METRICS", std::string("/") + names::kSensorMetricsTopic},
      {"SITE_MARKERS", std::string("/") + names::kSiteMarkersTopic},
      {"SURFACE_CLOUD", std::string("/") + names::kSurfaceCloudTopic},
      {"RECORDING_STATUS", names::kRecordingStatusTopic},
      {"SCENARIO", names::kScenarioTopic},
      {"CLOCK", names::kClockTopic},
      {"DIAGNOSTICS", names::kDiagnosticsTopic},
      {"RECEIVER_LINE_PREFIX", names::receiverLinePoint(0.0).substr(0, 6)},
      {"BUILDING_RESPONSE_FREE_FIELD_POINT", names::kBuildingResponseFreeFieldPoint},
  };
  for (const auto& [key, value] : expected) {
    ASSERT_TRUE(py.count(key)) << key << " missing from scripts/railvib_names.py";
    EXPECT_EQ(py.at(key), value) << key;
  }
  EXPECT_EQ(py.size(), expected.size()) << "a name in scripts/railvib_names.py the test does not know";
}

TEST(Names, PointAndFrameNames) {
  EXPECT_EQ(names::sensorFrame("ground_2m"), "sensor_ground_2m");
  EXPECT_EQ(names::tramBodyFrame("front_carbody"), "tram/front_carbody");
  EXPECT_EQ(names::buildingPointFrame("first_floor"), "building/first_floor");
  EXPECT_EQ(names::footprintPoint(3, 14), "footprint_3_14");
  EXPECT_EQ(names::receiverLinePoint(4.0), "line_y4");
  EXPECT_EQ(names::receiverLinePoint(1.5), "line_y1.5");
  EXPECT_EQ(names::buildingPlanPoint(0, 0), "bldg_front_left");
  EXPECT_EQ(names::buildingPlanPoint(1, 1), "bldg_centre");
  EXPECT_EQ(names::buildingPlanPoint(2, 2), "bldg_back_right");
  EXPECT_THROW(names::buildingPlanPoint(3, 0), std::out_of_range);
  EXPECT_EQ(names::sensorTopic("ground_2m", "imu"), "sensors/ground_2m/imu");
}
