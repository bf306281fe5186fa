// railvib/common: every topic, frame and output-point name of the project, in
// one place. The nodes, railvib_tool and the core loaders use these; the
// Python scripts mirror them in scripts/railvib_names.py (test_names checks
// the two agree).
//
// Frames (docs/DEVELOPING.md, "Sign conventions"): `track` (x along the
// track, y towards the building, z up; origin on the track axis at the
// defect), `building` (origin at the outer corner of the front wall at low x,
// axes parallel to `track`), one frame per virtual sensor, one per building
// response point, one per tram body.
#pragma once

#include <string>

namespace railvib::names {

// ---------------------------------------------------------------- frames
inline constexpr const char* kTrackFrame = "track";
inline constexpr const char* kBuildingFrame = "building";
/// Frame of a virtual sensor (always named after the sensor, never after its point).
inline std::string sensorFrame(const std::string& sensor_name) { return "sensor_" + sensor_name; }
/// Frame of a building response point (child of `building`).
inline std::string buildingPointFrame(const std::string& point_name) { return "building/" + point_name; }
/// Frame of a tram body (child of `track`, published on /tf by the vehicle node).
inline std::string tramBodyFrame(const std::string& body_name) { return "tram/" + body_name; }

// ---------------------------------------------------------------- streams (lossless blocks)
inline constexpr const char* kContactForcesTopic = "contact_forces";
inline constexpr const char* kSoilLoadsTopic = "soil_loads";
inline constexpr const char* kSurfaceVelocitiesTopic = "surface_velocities";
inline constexpr const char* kBuildingResponseTopic = "building_response";
inline constexpr const char* kSensorSamplesTopic = "sensor_samples";

// ---------------------------------------------------------------- layouts (latched) and other topics
inline constexpr const char* kSleeperLayoutTopic = "sleeper_layout";
inline constexpr const char* kSurfacePointsTopic = "surface_points";
inline constexpr const char* kBuildingPointsTopic = "building_points";
inline constexpr const char* kSurfaceSnapshotTopic = "surface_snapshot";
inline constexpr const char* kSectionSnapshotTopic = "section_snapshot";
inline constexpr const char* kSensorMetricsTopic = "sensor_metrics";
inline constexpr const char* kDiagnosticsTopic = "/diagnostics";
inline constexpr const char* kTfTopic = "/tf";
inline constexpr const char* kClockTopic = "/clock";
/// std_msgs/String (JSON) the recorder writes into its bag when it closes it: the streams it was
/// told to record, which of them are complete, and why it closed (scripts/bag_check.py reads it).
inline constexpr const char* kRecordingStatusTopic = "/railvib/recording";
/// std_msgs/String (YAML), latched and written first into the bag by the recorder: what produced
/// the run (railvib version, command line, config file, launch arguments, resolved config).
inline constexpr const char* kScenarioTopic = "/railvib/scenario";
inline constexpr const char* kSiteMarkersTopic = "visualization/site";
inline constexpr const char* kSurfaceCloudTopic = "visualization/surface_velocity";
/// Per-sensor topics: sensors/<name>/imu, .../velocity, .../metrics.
inline std::string sensorTopic(const std::string& sensor_name, const std::string& what) {
  return "sensors/" + sensor_name + "/" + what;
}

// ---------------------------------------------------------------- output points (soil receivers)
/// Receiver of the line perpendicular to the track (soil.output.receiver_line), at lateral position y.
std::string receiverLinePoint(double y_m);
/// Free-field receiver on the house plan: row 0 front wall, 1 middle, 2 back wall; column 0 low x,
/// 1 middle, 2 high x (bldg_front_left ... bldg_back_right; the middle one is bldg_centre).
std::string buildingPlanPoint(int row, int column);
/// Free-field receiver at the plan position of the house's response point.
inline constexpr const char* kBuildingResponseFreeFieldPoint = "bldg_response_point";
/// Footprint receiver (i along the length, j across the width) that drives the house's foundation.
inline std::string footprintPoint(int i, int j) { return "footprint_" + std::to_string(i) + "_" + std::to_string(j); }

}  // namespace railvib::names
