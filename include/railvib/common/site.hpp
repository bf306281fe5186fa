// railvib/common: the site geometry every domain shares, each value loaded and
// validated once, here, and handed on as a struct:
//   SiteLayout         rails, ground sensors and where the house stands (`site`)
//   BuildingPlacement  the house's plan outline and its frame's origin
//   TrackLayout        the sleepers and the modelled extent of the track (`track`)
//   PassageSpan        where and how long the vehicle runs (`simulation`)
//
// Frame `track`: x along the track (direction of travel), y lateral towards
// the building, z up; origin on the track axis at the defect, at the top of
// the soil. Frame `building`: origin at the outer corner of the front (long)
// wall at low x, on the ground surface, axes parallel to `track` (x along the
// front wall, y into the building, z up). Sensor frames: one per sensor, at
// the sensor, axes parallel to `track` (railvib/common/names.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"

namespace railvib {

struct NamedPoint {
  std::string name;
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
  /// The config entry that defines it (e.g. "virtual_sensors.sensors[0]"), for refusals; empty for
  /// a point the code places (the house's default response points).
  std::string key;
};

/// A virtual sensor placed by its own entry (virtual_sensors.sensors[i] with x_m and y_m): the entry
/// defines the point the sensor reads, named `point` (default: the sensor's name), so a sensor is
/// written once, with its position and its kind. kind free_field: a soil receiver at (x_m, y_m) of
/// frame track, on the surface; foundation or floor: a response point of the house at
/// (x_m, y_m, z_m) of frame building. An entry without a position reads a point defined elsewhere
/// (source and point: site.ground_sensors, the receiver line, building.response_points).
struct PlacedSensor {
  ConfigNode entry;    ///< virtual_sensors.sensors[i], for refusals that name its keys
  std::string sensor;  ///< the sensor's name
  bool in_house = false;
  NamedPoint point;  ///< key: the entry's path
};

/// The placed sensors of virtual_sensors.sensors, in list order (none without that section). Reads
/// only what placing needs (kind, point, x_m, y_m, z_m; the sensor loader reads the rest and checks
/// names); the house's own loader checks that a point lies in the house. Throws ConfigError.
std::vector<PlacedSensor> loadPlacedSensors(const ConfigNode& root);
/// Whether the entry places its sensor (has a position).
bool placesItsSensor(const ConfigNode& sensor_entry);

/// Where the house stands: its outer plan and the origin of frame `building` in frame `track`.
struct BuildingPlacement {
  double length_m = 0.0;  ///< along the track (building.length_m)
  double width_m = 0.0;   ///< across the track (building.width_m)
  double origin_x_m = 0.0;
  double origin_y_m = 0.0;
  double trackX(double x_building_m) const { return origin_x_m + x_building_m; }
  double trackY(double y_building_m) const { return origin_y_m + y_building_m; }
  /// Whether a point of frame track (m) lies on the house's outer plan, edges included.
  bool containsPlanPoint(double x_track_m, double y_track_m) const {
    return x_track_m >= origin_x_m && x_track_m <= origin_x_m + length_m && y_track_m >= origin_y_m &&
           y_track_m <= origin_y_m + width_m;
  }
};

struct SiteLayout {
  double rail_gauge_m = 1.435;
  /// Lateral position of the rail nearer to the building (y > 0).
  double exterior_rail_y_m = 0.7175;
  /// Free-field ground sensors (frame track, on the surface), names unique: site.ground_sensors,
  /// then the free-field sensors that virtual_sensors.sensors places (loadPlacedSensors).
  std::vector<NamedPoint> ground_sensors;
  /// The house, when the scenario has a `building` section.
  std::optional<BuildingPlacement> building;
};

/// The run of the vehicle: the only reader of simulation.speed_m_s, duration_s, front_axle_start_m.
struct PassageSpan {
  double speed_m_s = 30.0 / 3.6;
  double duration_s = 5.0;
  /// Front axle's position along the track at t = 0 (m, frame track).
  double front_axle_start_m = -11.666666666666666;
  /// Front axle's position at the end of the run.
  double frontAxleEndM() const { return front_axle_start_m + speed_m_s * duration_s; }
};

/// Positions of a vehicle's bodies behind its front axle (vehicles.<name>.bodies.<body>.x_m): one range
/// for the vehicle loader and for rearAxleOffsetM.
Range vehicleBodyPositionRange();

/// How the track's extent is set (track.extent.mode).
enum class TrackExtentMode { Fixed, Auto };

/// The sleepers (where the track hands its loads to the soil) and the modelled track.
struct TrackLayout {
  /// Sleepers at x = offset_m + k spacing_m inside [x_min_m, x_max_m].
  double spacing_m = 0.72;
  double offset_m = 0.0;
  double x_min_m = -50.0;
  double x_max_m = 50.0;
  /// fixed: x_min_m and x_max_m as given; auto: the whole vehicle for the whole run (from the rear
  /// axle at t = 0 to the front axle at the end) plus auto_margin_m and the end layer at each end.
  TrackExtentMode extent_mode = TrackExtentMode::Fixed;
  double auto_margin_m = 0.0;
  /// Absorbing end layer at each end (track.ends.absorbing_length_m), inside [x_min_m, x_max_m].
  double end_layer_m = 12.0;
  /// Footprint of a sleeper on the soil (length across the track, width along it).
  double length_m = 2.6;
  double width_m = 0.25;

  /// Index range [first, last] of k (may be empty: last < first).
  long firstIndex() const;
  long lastIndex() const;
  long sleeperCount() const { return lastIndex() - firstIndex() + 1; }
  /// Sleeper x positions, increasing.
  std::vector<double> sleeperPositions() const;
};

/// Read `site` (rail gauge, ground sensors, and the placed free-field sensors) and, with a `building`
/// section, the house's placement
/// (site.building, building.length_m and width_m). Throws ConfigError.
SiteLayout loadSiteLayout(const ConfigNode& root);
/// The house's placement (as in loadSiteLayout); without a `site` section, frame `building` at the
/// origin of frame `track` (building-only scenarios). Requires `building`.
BuildingPlacement loadBuildingPlacement(const ConfigNode& root);
/// Read track.sleeper (spacing_m, offset_m, length_m, width_m), track.extent and
/// track.ends.absorbing_length_m; with extent mode auto, also the passage (loadPassageSpan) and the
/// selected vehicle's rear axle (rearAxleOffsetM). Throws ConfigError.
TrackLayout loadTrackLayout(const ConfigNode& root);
/// Read simulation.speed_m_s, duration_s and front_axle_start_m. Throws ConfigError.
PassageSpan loadPassageSpan(const ConfigNode& root);
/// Offset of the selected vehicle's rear-most wheel behind its front axle (m): the body of the last
/// wheel of vehicles.<vehicle.name>.wheels (wheels are listed front to rear; the vehicle loader checks
/// the order and everything else). Throws ConfigError.
double rearAxleOffsetM(const ConfigNode& root);

}  // namespace railvib
