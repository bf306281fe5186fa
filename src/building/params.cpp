#include "railvib/building/params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "railvib/common/constants.hpp"

namespace railvib::building {
namespace {

ShellMaterial loadMaterial(const ConfigNode& node) {
  ShellMaterial m;
  m.young_modulus_pa = node.number("young_modulus_pa", Range::positive());
  m.shear_modulus_pa = node.number("shear_modulus_pa", Range::positive());
  m.density_kg_m3 = node.number("density_kg_m3", Range::positive());
  const double nu = m.poisson();
  if (!(nu > -1.0 && nu < 0.5)) {
    std::ostringstream os;
    os << "inconsistent with young_modulus_pa = " << m.young_modulus_pa << ": Poisson's ratio E/(2G) - 1 = " << nu
       << " is outside (-1, 0.5); an isotropic material needs G > E/3 = " << m.young_modulus_pa / 3.0 << " Pa";
    node.fail("shear_modulus_pa", os.str());
  }
  return m;
}

// A response point inside the house's bounds (the model checks that it lies on a wall or a slab).
void requireInHouse(const ConfigNode& node, const NamedPoint& pt, const BuildingParams& p) {
  auto check = [&](const char* key, double v, double lo, double hi) {
    if (v < lo || v > hi) {
      std::ostringstream os;
      os << "response point '" << pt.name << "' is outside the building: allowed [" << lo << ", " << hi
         << "] (building frame, origin at the outer front-left corner on the ground surface)";
      node.fail(key, os.str());
    }
  };
  check("x_m", pt.x_m, 0.0, p.length_m);
  check("y_m", pt.y_m, 0.0, p.width_m);
  check("z_m", pt.z_m, -p.foundation_depth_m, p.height_m);
}

NamedPoint loadPoint(const ConfigNode& node, const BuildingParams& p) {
  NamedPoint pt;
  pt.name = node.text("name");
  pt.x_m = node.number("x_m", Range::any());
  pt.y_m = node.number("y_m", Range::any());
  pt.z_m = node.number("z_m", Range::any());
  pt.key = node.keyPath();
  requireInHouse(node, pt, p);
  return pt;
}

}  // namespace

BuildingParams loadBuildingParams(const ConfigNode& root) {
  BuildingParams p;
  const ConfigNode b = root.section("building");
  p.placement = loadBuildingPlacement(root);
  p.length_m = p.placement.length_m;
  p.width_m = p.placement.width_m;
  p.height_m = b.number("height_m", Range::positive());
  p.storeys = static_cast<int>(b.integer("storeys", 1, 20));
  p.roof_slab = b.flag("roof_slab", false);

  const ConfigNode walls = b.section("walls");
  p.wall_thickness_m = walls.number("thickness_m", Range::positive());
  p.wall = loadMaterial(walls);
  const double plan_min = std::min(p.length_m, p.width_m);
  if (2.0 * p.wall_thickness_m >= plan_min) {
    walls.fail("thickness_m", "two walls of this thickness do not fit in the plan (" + std::to_string(p.length_m) +
                                  " m x " + std::to_string(p.width_m) + " m): need 2 t < min(length, width)");
  }
  const ConfigNode floors = b.section("floors");
  p.floor_thickness_m = floors.number("thickness_m", Range::positive());
  p.floor = loadMaterial(floors);
  const double storey_h = p.height_m / p.storeys;
  if (p.floor_thickness_m >= storey_h) {
    floors.fail("thickness_m", "a floor must be thinner than the storey height " + std::to_string(storey_h) + " m");
  }

  const ConfigNode f = b.section("foundation");
  p.foundation_depth_m = f.number("depth_m", Range::positive());
  p.foundation = loadMaterial(f);
  p.foundation_wall_thickness_m = f.number("wall_thickness_m", Range::positive(), p.wall_thickness_m);
  if (2.0 * p.foundation_wall_thickness_m >= plan_min) {
    f.fail("wall_thickness_m", "two foundation walls of this thickness do not fit in the plan");
  }
  p.base_slab_thickness_m = f.number("base_slab_thickness_m", Range::positive(), 0.25);
  if (p.base_slab_thickness_m >= p.foundation_depth_m) {
    f.fail("base_slab_thickness_m", "must be smaller than the foundation depth");
  }
  p.ground_slab_on_fill = f.flag("ground_slab_on_fill", true);
  p.foundation_model =
      f.choice("model", {"rigid", "meshed"}, "rigid") == "meshed" ? FoundationModel::Meshed : FoundationModel::Rigid;

  if (b.has("mesh")) {
    const ConfigNode mesh = b.section("mesh");
    p.element_size_m = mesh.number("element_size_m", Range::closed(0.05, 5.0), p.element_size_m);
  }
  if (p.element_size_m > 0.5 * plan_min) {
    b.section("mesh").fail("element_size_m", "must be at most half the smaller plan dimension");
  }
  if (b.has("damping")) {
    const ConfigNode d = b.section("damping");
    p.damping_ratio = d.number("ratio", Range{0.0, 0.5, false, true}, p.damping_ratio);
    p.damping_f1_hz = d.number("f1_hz", Range::positive(), p.damping_f1_hz);
    p.damping_f2_hz = d.number("f2_hz", Range::positive(), p.damping_f2_hz);
    if (p.damping_f2_hz <= p.damping_f1_hz) d.fail("f2_hz", "must be larger than f1_hz");
  }
  if (b.has("solver")) {
    p.max_time_step_s = b.section("solver").number("max_time_step_s", Range{0.0, 0.01, true, false}, p.max_time_step_s);
  }
  p.coupling = b.choice("coupling", {"one_way", "two_way"}, "one_way") == "two_way" ? SoilCoupling::TwoWay
                                                                                    : SoilCoupling::OneWay;
  p.coupling_modes_max_hz = b.number("coupling_modes_max_hz", Range::nonNegative(), 0.0);
  if (b.has("footprint")) {
    const ConfigNode fp = b.section("footprint");
    p.footprint_nx = static_cast<int>(fp.integer("nx", 2, 100, p.footprint_nx));
    p.footprint_ny = static_cast<int>(fp.integer("ny", 2, 100, p.footprint_ny));
  }
  const bool listed = b.has("response_points");
  if (listed) {
    for (const ConfigNode& n : b.sectionList("response_points")) p.response_points.push_back(loadPoint(n, p));
  } else {
    // [paper] middle of the width, three quarters along the length, ground and first floor.
    p.response_points.push_back({"ground_floor", 0.75 * p.length_m, 0.5 * p.width_m, 0.0, ""});
    if (p.storeys > 1) p.response_points.push_back({"first_floor", 0.75 * p.length_m, 0.5 * p.width_m, storey_h, ""});
  }
  for (size_t i = 0; i < p.response_points.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (p.response_points[i].name == p.response_points[j].name) {
        b.fail("response_points", "duplicate response point name '" + p.response_points[i].name + "'");
      }
    }
  }
  // The points the house's sensors place (virtual_sensors.sensors with a position): one of the
  // default points of that name gives way to it; a listed one would be a second definition.
  for (const PlacedSensor& s : loadPlacedSensors(root)) {
    if (!s.in_house) continue;
    requireInHouse(s.entry, s.point, p);
    auto same = std::find_if(p.response_points.begin(), p.response_points.end(),
                             [&](const NamedPoint& q) { return q.name == s.point.name; });
    if (same != p.response_points.end() && !same->key.empty()) {
      s.entry.fail(s.entry.has("point") ? "point" : "name",
                   "the point '" + s.point.name + "' is defined twice (" + same->key + " and this sensor's position)");
    }
    if (same != p.response_points.end()) {
      *same = s.point;
    } else {
      p.response_points.push_back(s.point);
    }
  }
  if (b.has("openings")) {
    for (const ConfigNode& n : b.sectionList("openings")) {
      Opening o;
      o.wall = n.choice("wall", {"front", "back", "left", "right"});
      o.start_m = n.number("start_m", Range::nonNegative());
      o.bottom_m = n.number("bottom_m", Range::nonNegative());
      o.width_m = n.number("width_m", Range::positive());
      o.height_m = n.number("height_m", Range::positive());
      const double wall_len = (o.wall == "front" || o.wall == "back") ? p.length_m : p.width_m;
      if (o.start_m + o.width_m > wall_len) n.fail("width_m", "the opening runs past the end of the wall");
      if (o.bottom_m + o.height_m > p.height_m) n.fail("height_m", "the opening runs past the top of the wall");
      p.openings.push_back(o);
    }
  }

  if (b.has("interior_walls")) {
    for (const ConfigNode& n : b.sectionList("interior_walls")) {
      InteriorWall w;
      w.along = n.choice("along", {"x", "y"});
      const double span = w.along == "x" ? p.width_m : p.length_m;
      w.position_m = n.number("position_m", Range::open(p.wall_thickness_m, span - p.wall_thickness_m));
      p.interior_walls.push_back(w);
    }
  }
  return p;
}

RayleighCoefficients rayleighCoefficients(const BuildingParams& p) {
  const double w1 = kTwoPi * p.damping_f1_hz, w2 = kTwoPi * p.damping_f2_hz;
  return {2.0 * p.damping_ratio * w1 * w2 / (w1 + w2), 2.0 * p.damping_ratio / (w1 + w2)};
}

}  // namespace railvib::building
