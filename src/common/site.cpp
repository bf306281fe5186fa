#include "railvib/common/site.hpp"

#include <cmath>
#include <set>

namespace railvib {

namespace {

// The house's plan: the only reader of building.length_m and building.width_m.
BuildingPlacement buildingPlan(const ConfigNode& root) {
  const ConfigNode building = root.section("building");
  BuildingPlacement p;
  p.length_m = building.number("length_m", Range::positive());
  p.width_m = building.number("width_m", Range::positive());
  return p;
}

}  // namespace

SiteLayout loadSiteLayout(const ConfigNode& root) {
  const ConfigNode site = root.section("site");
  SiteLayout layout;
  layout.rail_gauge_m = site.number("rail_gauge_m", Range::open(0.5, 2.0));
  layout.exterior_rail_y_m = 0.5 * layout.rail_gauge_m;
  std::set<std::string> names;
  for (const ConfigNode& sensor : site.sectionList("ground_sensors")) {
    NamedPoint p;
    p.name = sensor.text("name");
    p.x_m = sensor.number("x_m", Range::open(-1.0e5, 1.0e5));
    p.y_m = sensor.number("y_m", Range::open(-1.0e5, 1.0e5));
    if (!names.insert(p.name).second) sensor.fail("name", "duplicate sensor name");
    layout.ground_sensors.push_back(p);
  }
  if (root.has("building")) {
    BuildingPlacement placement = buildingPlan(root);
    const ConfigNode building = site.section("building");
    // The front wall is centred on center_x_m: the frame origin is its low-x outer corner.
    placement.origin_x_m = building.number("center_x_m", Range::open(-1.0e5, 1.0e5)) - 0.5 * placement.length_m;
    placement.origin_y_m =
        layout.exterior_rail_y_m + building.number("front_wall_distance_from_rail_m", Range::positive());
    layout.building = placement;
  }
  return layout;
}

BuildingPlacement loadBuildingPlacement(const ConfigNode& root) {
  if (!root.has("site")) return buildingPlan(root);
  return *loadSiteLayout(root).building;
}

long TrackLayout::firstIndex() const { return static_cast<long>(std::ceil((x_min_m - offset_m) / spacing_m - 1e-9)); }

long TrackLayout::lastIndex() const { return static_cast<long>(std::floor((x_max_m - offset_m) / spacing_m + 1e-9)); }

std::vector<double> TrackLayout::sleeperPositions() const {
  std::vector<double> x;
  for (long k = firstIndex(); k <= lastIndex(); ++k) x.push_back(offset_m + static_cast<double>(k) * spacing_m);
  return x;
}

TrackLayout loadTrackLayout(const ConfigNode& root) {
  const ConfigNode track = root.section("track");
  const ConfigNode sleeper = track.section("sleeper");
  TrackLayout layout;
  // Real sleeper spacings are 0.6-0.75 m; the bounds keep the sleeper indices far from overflow.
  layout.spacing_m = sleeper.number("spacing_m", Range::closed(0.05, 5.0));
  layout.offset_m = sleeper.number("offset_m", Range::open(-1.0e5, 1.0e5), 0.0);
  layout.length_m = sleeper.number("length_m", Range::open(0.0, 10.0));
  layout.width_m = sleeper.number("width_m", Range::open(0.0, 10.0));
  const ConfigNode extent = track.section("extent");
  layout.x_min_m = extent.number("x_min_m", Range::open(-1.0e5, 1.0e5));
  layout.x_max_m = extent.number("x_max_m", Range::open(-1.0e5, 1.0e5));
  if (!(layout.x_max_m > layout.x_min_m)) extent.fail("x_max_m", "must be greater than x_min_m");
  return layout;
}

}  // namespace railvib
