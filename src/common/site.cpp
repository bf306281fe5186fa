#include "railvib/common/site.hpp"

#include <set>

namespace railvib {

SiteLayout loadSiteLayout(const Config& config) {
  const ConfigNode site = config.section("site");
  SiteLayout layout;
  layout.rail_gauge_m = site.number("rail_gauge_m", Range::open(0.5, 2.0));
  layout.exterior_rail_y_m = 0.5 * layout.rail_gauge_m;
  const ConfigNode building = site.section("building");
  // The front wall is centred on center_x_m: the frame origin is its low-x outer corner.
  const double length_m = config.section("building").number("length_m", Range::positive());
  layout.building_origin_x_m = building.number("center_x_m", Range::any()) - 0.5 * length_m;
  layout.building_origin_y_m =
      layout.exterior_rail_y_m + building.number("front_wall_distance_from_rail_m", Range::positive());
  std::set<std::string> names;
  for (const ConfigNode& sensor : site.sectionList("ground_sensors")) {
    NamedPoint p;
    p.name = sensor.text("name");
    p.x_m = sensor.number("x_m", Range::any());
    p.y_m = sensor.number("y_m", Range::any());
    if (!names.insert(p.name).second) sensor.fail("name", "duplicate sensor name");
    layout.ground_sensors.push_back(p);
  }
  return layout;
}

}  // namespace railvib
