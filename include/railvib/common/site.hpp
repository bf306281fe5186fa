// railvib/common: the site geometry every domain shares, each value loaded and
// validated once, here, and handed on as a struct:
//   SiteLayout         rails, ground sensors and where the house stands (`site`)
//   BuildingPlacement  the house's plan outline and its frame's origin
//   TrackLayout        the sleepers and the modelled extent of the track (`track`)
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
};

/// Where the house stands: its outer plan and the origin of frame `building` in frame `track`.
struct BuildingPlacement {
  double length_m = 0.0;  ///< along the track (building.length_m)
  double width_m = 0.0;   ///< across the track (building.width_m)
  double origin_x_m = 0.0;
  double origin_y_m = 0.0;
  double trackX(double x_building_m) const { return origin_x_m + x_building_m; }
  double trackY(double y_building_m) const { return origin_y_m + y_building_m; }
};

struct SiteLayout {
  double rail_gauge_m = 1.435;
  /// Lateral position of the rail nearer to the building (y > 0).
  double exterior_rail_y_m = 0.7175;
  /// Free-field ground sensors (frame track, on the surface), names unique.
  std::vector<NamedPoint> ground_sensors;
  /// The house, when the scenario has a `building` section.
  std::optional<BuildingPlacement> building;
};

/// The sleepers (where the track hands its loads to the soil) and the modelled track.
struct TrackLayout {
  /// Sleepers at x = offset_m + k spacing_m inside [x_min_m, x_max_m].
  double spacing_m = 0.72;
  double offset_m = 0.0;
  double x_min_m = -50.0;
  double x_max_m = 50.0;
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

/// Read `site` (rail gauge, ground sensors) and, with a `building` section, the house's placement
/// (site.building, building.length_m and width_m). Throws ConfigError.
SiteLayout loadSiteLayout(const ConfigNode& root);
/// The house's placement (as in loadSiteLayout); without a `site` section, frame `building` at the
/// origin of frame `track` (building-only scenarios). Requires `building`.
BuildingPlacement loadBuildingPlacement(const ConfigNode& root);
/// Read track.sleeper (spacing_m, offset_m, length_m, width_m) and track.extent. Throws ConfigError.
TrackLayout loadTrackLayout(const ConfigNode& root);

}  // namespace railvib
