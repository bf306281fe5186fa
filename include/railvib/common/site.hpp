// railvib/common: site geometry shared by every domain and the tf frames.
//
// Frame `track`: x along the track (direction of travel), y lateral towards
// the building, z up; origin on the track axis at the defect, at the top of
// the soil. Frame `building`: origin at the outer corner of the front (long)
// wall at low x, on the ground surface, axes parallel to `track` (x along the
// front wall, y into the building, z up). Sensor frames: one per sensor, at
// the sensor, axes parallel to `track`.
#pragma once

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

struct SiteLayout {
  double rail_gauge_m = 1.435;
  /// Lateral position of the rail nearer to the building (y > 0).
  double exterior_rail_y_m = 0.7175;
  /// Origin of frame `building` in frame `track`.
  double building_origin_x_m = 0.0;
  double building_origin_y_m = 0.0;
  /// Free-field ground sensors (frame track, on the surface).
  std::vector<NamedPoint> ground_sensors;
};

/// Read the `site` section of a scenario (validated).
SiteLayout loadSiteLayout(const Config& config);

}  // namespace railvib
