#include "railvib/common/site.hpp"

#include <cmath>
#include <set>
#include <sstream>

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

bool placesItsSensor(const ConfigNode& sensor_entry) { return sensor_entry.has("x_m") || sensor_entry.has("y_m"); }

std::vector<PlacedSensor> loadPlacedSensors(const ConfigNode& root) {
  std::vector<PlacedSensor> placed;
  if (!root.has("virtual_sensors")) return placed;
  for (const ConfigNode& entry : root.section("virtual_sensors").sectionList("sensors")) {
    if (!placesItsSensor(entry)) continue;
    PlacedSensor s{entry, entry.text("name"), false, {}};
    // Its kind says where it stands: there is no source to give beside a position.
    const std::string kind = entry.choice("kind", {"free_field", "foundation", "floor"});
    if (entry.has("source")) {
      entry.fail("source", "a sensor with a position (x_m, y_m) takes its source from its kind (" + kind +
                               "); give a position and a kind, or a source and a point defined elsewhere");
    }
    s.in_house = kind != "free_field";
    s.point.name = entry.text("point", s.sensor);
    s.point.key = entry.keyPath();
    s.point.x_m = entry.number("x_m", Range::open(-1.0e5, 1.0e5));
    s.point.y_m = entry.number("y_m", Range::open(-1.0e5, 1.0e5));
    if (s.in_house) {
      s.point.z_m = entry.number("z_m", Range::open(-1.0e5, 1.0e5));
    } else if (entry.has("z_m")) {
      entry.fail("z_m", "a free-field sensor stands on the ground surface (frame track, z = 0)");
    }
    placed.push_back(s);
  }
  return placed;
}

SiteLayout loadSiteLayout(const ConfigNode& root) {
  const ConfigNode site = root.section("site");
  SiteLayout layout;
  layout.rail_gauge_m = site.number("rail_gauge_m", Range::open(0.5, 2.0));
  layout.exterior_rail_y_m = 0.5 * layout.rail_gauge_m;
  std::set<std::string> names;
  // Optional: the free-field sensors may all be placed in virtual_sensors.sensors.
  if (site.has("ground_sensors")) {
    for (const ConfigNode& sensor : site.sectionList("ground_sensors")) {
      NamedPoint p;
      p.name = sensor.text("name");
      p.x_m = sensor.number("x_m", Range::open(-1.0e5, 1.0e5));
      p.y_m = sensor.number("y_m", Range::open(-1.0e5, 1.0e5));
      p.key = sensor.keyPath();
      if (!names.insert(p.name).second) sensor.fail("name", "duplicate sensor name");
      layout.ground_sensors.push_back(p);
    }
  }
  for (const PlacedSensor& s : loadPlacedSensors(root)) {
    if (s.in_house) continue;
    if (!names.insert(s.point.name).second) {
      s.entry.fail(s.entry.has("point") ? "point" : "name",
                   "the point '" + s.point.name +
                       "' is defined twice (in site.ground_sensors, or by another sensor's position)");
    }
    layout.ground_sensors.push_back(s.point);
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

Range vehicleBodyPositionRange() { return Range::closed(-100.0, 200.0); }

PassageSpan loadPassageSpan(const ConfigNode& root) {
  const ConfigNode s = root.section("simulation");
  PassageSpan span;
  span.speed_m_s = s.number("speed_m_s", Range::open(0.0, 100.0));
  span.duration_s = s.number("duration_s", Range::open(0.0, 600.0));
  span.front_axle_start_m = s.number("front_axle_start_m", Range::open(-1.0e5, 1.0e5));
  return span;
}

double rearAxleOffsetM(const ConfigNode& root) {
  const ConfigNode library = root.section("vehicles");
  const std::string name = root.section("vehicle").text("name");
  if (!library.has(name)) root.section("vehicle").fail("name", "no vehicle '" + name + "' in the library `vehicles`");
  const ConfigNode vehicle = library.section(name);
  const std::vector<ConfigNode> wheels = vehicle.sectionList("wheels");
  if (wheels.empty()) vehicle.fail("wheels", "a vehicle needs at least one wheel");
  const std::string body = wheels.back().text("body");
  const ConfigNode bodies = vehicle.section("bodies");
  if (!bodies.has(body)) wheels.back().fail("body", "no body " + bodies.childPath(body));
  const double x = bodies.section(body).number("x_m", vehicleBodyPositionRange());
  if (x < 0.0) {
    std::ostringstream why;
    why << "the rear wheel's body lies ahead of the front axle (x_m = " << x << " m)";
    wheels.back().fail("body", why.str());
  }
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
  const bool automatic = extent.choice("mode", {"fixed", "auto"}) == "auto";
  // Required by the track model and by an automatic extent (a missing section names a near-miss key:
  // "is 'track.endss' a misspelling of it?"); layouts that only place sleepers may leave it out.
  layout.end_layer_m = track.has("ends") || automatic
                           ? track.section("ends").number("absorbing_length_m", Range{0.0, 1.0e4, false, true})
                           : 0.0;
  if (!automatic) {
    layout.x_min_m = extent.number("x_min_m", Range::open(-1.0e5, 1.0e5));
    layout.x_max_m = extent.number("x_max_m", Range::open(-1.0e5, 1.0e5));
    // Kept for mode auto (an override switching the mode need not delete it): still a valid margin.
    if (extent.has("margin_m")) extent.number("margin_m", Range::closed(0.0, 1.0e3));
    if (!(layout.x_max_m > layout.x_min_m)) extent.fail("x_max_m", "must be greater than x_min_m");
    return layout;
  }
  // The vehicle stays on ordinary track (outside the end layers) for the whole run, by construction.
  for (const char* key : {"x_min_m", "x_max_m"}) {
    if (extent.has(key)) extent.fail(key, "mode: auto computes the extent from the run (give mode: fixed to set it)");
  }
  layout.extent_mode = TrackExtentMode::Auto;
  layout.auto_margin_m = extent.number("margin_m", Range::closed(0.0, 1.0e3));
  const PassageSpan span = loadPassageSpan(root);
  const double pad = layout.auto_margin_m + layout.end_layer_m;
  layout.x_min_m = span.front_axle_start_m - rearAxleOffsetM(root) - pad;
  layout.x_max_m = span.frontAxleEndM() + pad;
  return layout;
}

}  // namespace railvib
