#include "railvib/coupling/house_foundation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "railvib/soil/boundary.hpp"

namespace railvib::coupling {

namespace {

// q_building = D q_soil.
Eigen::Matrix<double, 6, 6> frameChange() {
  Eigen::Matrix<double, 6, 1> d;
  d << 1.0, 1.0, -1.0, -1.0, -1.0, 1.0;
  return d.asDiagonal();
}

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The house's fixed-interface modes kept in the reduction (Hz): building.coupling_modes_max_hz, 0 meaning
// twice the soil's resolved frequency.
double couplingModesMaxHz(const building::BuildingParams& bp, const soil::SoilParams& sp) {
  return bp.coupling_modes_max_hz > 0.0 ? bp.coupling_modes_max_hz : 2.0 * sp.mesh.f_max_hz;
}

}  // namespace

std::vector<soil::InclusionSpec> meshedFoundation(const building::BuildingParams& bp, const soil::SoilParams& sp) {
  // The soil mesh's node planes (its inclusions aside): each face of the box goes to the nearest one, as the
  // rigid body's do, and each wall and slab keeps at least one element of thickness.
  soil::MeshSpec plain = sp.mesh;
  plain.inclusions.clear();
  const soil::StructuredMesh m = soil::buildMesh(sp.profile, plain);
  auto nearestIndex = [](double v, double v0, double h, size_t n) {
    return std::clamp<long>(std::lround((v - v0) / h), 0L, static_cast<long>(n));
  };
  auto elements = [](double thickness, double h) { return std::max(1L, std::lround(thickness / h)); };
  const double x0 = bp.placement.origin_x_m, y0 = bp.placement.origin_y_m;
  const long i0 = nearestIndex(x0, m.x0, m.hx, m.nx), i1 = nearestIndex(x0 + bp.length_m, m.x0, m.hx, m.nx);
  const long j0 = nearestIndex(y0, m.y0, m.hy, m.ny), j1 = nearestIndex(y0 + bp.width_m, m.y0, m.hy, m.ny);
  const long wx = elements(bp.foundation_wall_thickness_m, m.hx), wy = elements(bp.foundation_wall_thickness_m, m.hy);
  auto nearestLevel = [&](double depth) {
    size_t best = 0;
    for (size_t k = 0; k <= m.nz; ++k)
      if (std::abs(m.z[k] - depth) < std::abs(m.z[best] - depth)) best = k;
    return static_cast<long>(best);
  };
  // The slabs keep their thickness in elements (as the walls), from the bottom and from the surface: a
  // face snapped on its own could double a slab thinner than an element.
  const long k_bottom = std::max(1L, nearestLevel(bp.foundation_depth_m));
  const long k_base = k_bottom - elements(bp.base_slab_thickness_m, m.z[k_bottom] - m.z[k_bottom - 1]);
  const long k_top = bp.ground_slab_on_fill ? elements(bp.floor_thickness_m, m.z[1] - m.z[0]) : 0L;
  if (i1 - i0 < 2 * wx + 1 || j1 - j0 < 2 * wy + 1 || k_base <= k_top) {
    std::ostringstream os;
    os << "building.foundation.model meshed: the soil mesh is too coarse for the foundation box (its walls and "
          "slabs need one element each and room between them): elements "
       << m.hx << " x " << m.hy << " m in plan and " << (m.z[1] - m.z[0]) << " m deep at the surface against walls "
       << bp.foundation_wall_thickness_m << " m and a box " << bp.foundation_depth_m
       << " m deep; refine soil.mesh (f_max_hz, elements_per_wavelength) or take building.foundation.model: rigid";
    throw std::invalid_argument(os.str());
  }
  soil::Material concrete{bp.foundation.young_modulus_pa, bp.foundation.density_kg_m3, bp.foundation.poisson()};
  auto box = [&](const std::string& name, long a0, long a1, long b0, long b1, long c0, long c1) {
    soil::InclusionSpec s;
    s.name = "house_foundation_" + name;
    s.material = concrete;
    s.implicit = true;
    // The house's concrete damping: the stiffness-proportional part of its Rayleigh damping (the mass
    // part would damp the box's rigid motion in the soil).
    s.rayleigh_beta_s = building::rayleighCoefficients(bp).beta_s;
    s.x_min_m = m.x(static_cast<size_t>(a0)), s.x_max_m = m.x(static_cast<size_t>(a1));
    s.y_min_m = m.y(static_cast<size_t>(b0)), s.y_max_m = m.y(static_cast<size_t>(b1));
    s.top_m = m.z[static_cast<size_t>(c0)], s.bottom_m = m.z[static_cast<size_t>(c1)];
    return s;
  };
  std::vector<soil::InclusionSpec> out;
  out.push_back(box("base_slab", i0, i1, j0, j1, k_base, k_bottom));
  if (k_top > 0) out.push_back(box("ground_slab", i0, i1, j0, j1, 0, k_top));
  out.push_back(box("front_wall", i0, i1, j0, j0 + wy, k_top, k_base));
  out.push_back(box("back_wall", i0, i1, j1 - wy, j1, k_top, k_base));
  out.push_back(box("left_wall", i0, i0 + wx, j0 + wy, j1 - wy, k_top, k_base));
  out.push_back(box("right_wall", i1 - wx, i1, j0 + wy, j1 - wy, k_top, k_base));
  return out;
}

std::vector<soil::InclusionSpec> checkHouseInSoil(const ConfigNode& root, const building::BuildingParams& bp,
                                                  const soil::SoilParams& sp) {
  const ConfigNode bld = root.section("building");
  const ConfigNode site_building = root.section("site").section("building");
  // Placement: the foundation box in the track frame (x, y; depth below the surface).
  const double x0 = bp.placement.origin_x_m, x1 = x0 + bp.length_m;
  const double y0 = bp.placement.origin_y_m, y1 = y0 + bp.width_m;
  const double depth = bp.foundation_depth_m;
  const std::unique_ptr<soil::SoilBoundary> boundary = soil::makeSoilBoundary(sp.solver.boundary);
  const double zone = boundary->zoneThicknessM();
  if (x0 < sp.mesh.x_min_m + zone || x1 > sp.mesh.x_max_m - zone || y0 < sp.mesh.y_min_m + zone ||
      y1 > sp.mesh.y_max_m - zone) {
    site_building.fail("center_x_m", "the house's footprint x [" + str(x0) + ", " + str(x1) + "] m, y [" + str(y0) +
                                         ", " + str(y1) + "] m is not inside the soil box (soil.mesh) clear of its " +
                                         str(zone) + " m absorbing zone");
  }
  if (depth >= sp.mesh.depth_m - (boundary->zoneAlongBottom() ? zone : 0.0)) {
    bld.section("foundation")
        .fail("depth_m", "the foundation reaches below the soil mesh (depth " + str(sp.mesh.depth_m) +
                             " m, absorbing zone included)");
  }
  const double sleeper_half_length = 0.5 * sp.track.length_m;
  if (y0 <= sleeper_half_length) {
    site_building.fail("front_wall_distance_from_rail_m",
                       "the house's front wall (y = " + str(y0) +
                           " m) overlaps the track: the sleepers reach y = " + str(sleeper_half_length) + " m");
  }
  if (couplingModesMaxHz(bp, sp) < 2.0 * sp.mesh.f_max_hz) {
    bld.fail("coupling_modes_max_hz",
             "the reduction must keep the house's modes up to at least twice the soil's "
             "resolved frequency (2 x soil.mesh.f_max_hz = " +
                 str(2.0 * sp.mesh.f_max_hz) + " Hz)");
  }

  if (bp.foundation_model != building::FoundationModel::Meshed) return {};
  try {
    return meshedFoundation(bp, sp);
  } catch (const std::invalid_argument& e) {
    bld.section("foundation").fail("model", e.what());
  }
  return {};
}

HouseFoundation houseFoundation(const ConfigNode& root, const building::BuildingModel& model,
                                const soil::SoilParams& sp) {
  const building::BuildingParams& bp = model.params();
  std::vector<soil::InclusionSpec> inclusions = checkHouseInSoil(root, bp, sp);
  const double x0 = bp.placement.origin_x_m, x1 = x0 + bp.length_m;
  const double y0 = bp.placement.origin_y_m, y1 = y0 + bp.width_m;
  const double depth = bp.foundation_depth_m;
  const double fmax = couplingModesMaxHz(bp, sp);
  HouseFoundation h;
  h.model = bp.foundation_model;
  const Eigen::Vector3d centre_building(0.5 * bp.length_m, 0.5 * bp.width_m, 0.0);
  h.reduction = building::reduceOnRigidBase(model, fmax, centre_building);
  const Eigen::Matrix<double, 6, 6> d = frameChange();
  soil::RigidBodySpec& b = h.body;
  b.name = "house_foundation";
  b.x_min_m = x0;
  b.x_max_m = x1;
  b.y_min_m = y0;
  b.y_max_m = y1;
  b.depth_m = depth;
  // The mesh does not follow the walls: the box's faces go to the nearest node lines and plane.
  b.snap_to_nearest = true;
  b.reference_m = Eigen::Vector3d(x0 + 0.5 * bp.length_m, y0 + 0.5 * bp.width_m, 0.0);
  // Concrete of the box (the foundation DOFs of the house model) in excess of the soil it displaces.
  const double rho_soil = sp.profile.front().material.density_kg_m3;
  const double ratio = rho_soil / bp.foundation.density_kg_m3;
  h.concrete_mass_kg = h.reduction.foundation_rigid_mass(0, 0);
  h.displaced_soil_mass_kg = ratio * h.concrete_mass_kg;
  b.added_mass = d * ((1.0 - ratio) * h.reduction.foundation_rigid_mass) * d;
  if (h.model == building::FoundationModel::Meshed) {
    // The concrete is in the soil mesh; the house stands on the tops of the box's walls, its rigid
    // interface (the Craig-Bampton reduction's), carried as a ring of surface nodes.
    h.inclusions = std::move(inclusions);
    b.added_mass.setZero();
    b.depth_m = 0.0;
    b.ring_width_m = bp.foundation_wall_thickness_m;
  }
  soil::ReducedStructure& st = b.structure;
  st.rigid_mass = d * h.reduction.superstructure_rigid_mass * d;
  st.participation = h.reduction.participation * d;
  st.circular_frequency_rad_s = h.reduction.circular_frequency_rad_s;
  st.damping_ratio = h.reduction.damping_ratio;
  return h;
}

std::vector<soil::RigidBodySpec> attachHouse(const ConfigNode& root, soil::SoilParams& soil_params) {
  if (!root.has("building")) return {};
  const building::BuildingModel house(building::loadBuildingParams(root));
  if (house.params().coupling != building::SoilCoupling::TwoWay) return {};
  const HouseFoundation h = houseFoundation(root, house, soil_params);
  for (const soil::InclusionSpec& inc : h.inclusions) {
    for (const soil::InclusionSpec& other : soil_params.mesh.inclusions) {
      if (other.name == inc.name) {
        root.section("soil").fail("inclusions", "'" + inc.name + "' is the name of the house's meshed foundation");
      }
    }
    soil_params.mesh.inclusions.push_back(inc);
  }
  return {h.body};
}

soil::HouseReceivers houseReceivers(const ConfigNode& root, bool include_footprint) {
  soil::HouseReceivers house;
  if (!root.has("building")) return house;
  const building::BuildingParams params = building::loadBuildingParams(root);
  house.free_field = building::freeFieldPoints(params);
  // The house is driven at its foundation nodes: each becomes a soil receiver.
  if (include_footprint) {
    for (const auto& f : building::footprintPoints(params)) {
      house.footprint.push_back({f.name, f.x_track_m, f.y_track_m, f.z_track_m, ""});
    }
  }
  return house;
}

}  // namespace railvib::coupling
