#include "railvib/coupling/house_foundation.hpp"

#include <sstream>

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

}  // namespace

HouseFoundation houseFoundation(const ConfigNode& root, const building::BuildingModel& model,
                                const soil::SoilParams& sp) {
  const building::BuildingParams& bp = model.params();
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
  const double fmax = bp.coupling_modes_max_hz > 0.0 ? bp.coupling_modes_max_hz : 2.0 * sp.mesh.f_max_hz;
  if (fmax < 2.0 * sp.mesh.f_max_hz) {
    bld.fail("coupling_modes_max_hz",
             "the reduction must keep the house's modes up to at least twice the soil's "
             "resolved frequency (2 x soil.mesh.f_max_hz = " +
                 str(2.0 * sp.mesh.f_max_hz) + " Hz)");
  }

  HouseFoundation h;
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
  soil::ReducedStructure& st = b.structure;
  st.rigid_mass = d * h.reduction.superstructure_rigid_mass * d;
  st.participation = h.reduction.participation * d;
  st.circular_frequency_rad_s = h.reduction.circular_frequency_rad_s;
  st.damping_ratio = h.reduction.damping_ratio;
  return h;
}

std::vector<soil::RigidBodySpec> attachedBodies(const ConfigNode& root, const soil::SoilParams& soil_params) {
  if (!root.has("building")) return {};
  const building::BuildingModel house(building::loadBuildingParams(root));
  if (house.params().coupling != building::SoilCoupling::TwoWay) return {};
  return {houseFoundation(root, house, soil_params).body};
}

soil::HouseReceivers houseReceivers(const ConfigNode& root, bool include_footprint) {
  soil::HouseReceivers house;
  if (!root.has("building")) return house;
  const building::BuildingParams params = building::loadBuildingParams(root);
  house.free_field = building::freeFieldPoints(params);
  // The house is driven at its foundation nodes: each becomes a soil receiver.
  if (include_footprint) {
    for (const auto& f : building::footprintPoints(params)) {
      house.footprint.push_back({f.name, f.x_track_m, f.y_track_m, f.z_track_m});
    }
  }
  return house;
}

}  // namespace railvib::coupling
