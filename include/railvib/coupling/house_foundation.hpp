// railvib/coupling: the house standing on the soil (two-way soil-structure interaction).
//
// Composes the two domains without mixing them: the building domain reduces
// the house on its rigid foundation (building/reduction.hpp), the soil domain
// carries a rigid body with a reduced structure (soil/rigid_body.hpp); this
// file turns the one into the other. The foundation is the paper's embedded
// concrete box: the soil nodes inside the house's plan down to the foundation
// depth move rigidly; the box weighs its concrete plus the fill inside (the
// carried soil nodes hold the soil mass of the whole box volume, so the
// concrete's excess over the soil it displaces is added). Frames: the soil's
// rigid DOFs are (u_x, u_y, u_d, w_x, w_y, w_d) in x, y, d = depth down; the
// building's (U, Theta) in x, y, z up with right-handed rotations, so
// q_building = D q_soil with D = diag(1, 1, -1, -1, -1, 1).
#pragma once

#include <vector>

#include "railvib/building/model.hpp"
#include "railvib/building/reduction.hpp"
#include "railvib/common/config.hpp"
#include "railvib/soil/rigid_body.hpp"
#include "railvib/soil/soil_params.hpp"

namespace railvib::coupling {

struct HouseFoundation {
  soil::RigidBodySpec body;
  building::RigidBaseReduction reduction;
  /// Mass of the concrete of the foundation box (kg) and the soil it displaces (kg).
  double concrete_mass_kg = 0.0, displaced_soil_mass_kg = 0.0;
  building::FoundationModel model = building::FoundationModel::Rigid;
  /// Meshed: the box's concrete as implicit soil inclusions (meshedFoundation), the body a ring of the
  /// walls' tops with no added mass.
  std::vector<soil::InclusionSpec> inclusions;
};

/// The foundation box of `params` as concrete soil inclusions, aligned with the node planes of the soil mesh
/// of `soil_params` (each face at the nearest plane, each wall and slab at least one element thick): base
/// slab, ground slab (when it rests on the fill), four walls between them; implicit and undamped
/// (soil/implicit_unit.hpp). Throws std::invalid_argument when the mesh is too coarse for the box.
std::vector<soil::InclusionSpec> meshedFoundation(const building::BuildingParams& params,
                                                  const soil::SoilParams& soil_params);

/// What the two-way coupling requires of the house in the soil, checked without building the house's
/// reduction (so `config-check` refuses what the soil node would): the placement (inside the soil box and
/// outside its absorbing zone, not deeper than the mesh, clear of the track's sleepers), the mode cut-off,
/// and for a meshed foundation that the mesh holds the box. Refuses with the key path (ConfigError);
/// returns the meshed box's inclusions (empty for a rigid one).
std::vector<soil::InclusionSpec> checkHouseInSoil(const ConfigNode& root, const building::BuildingParams& params,
                                                  const soil::SoilParams& soil_params);

/// The soil's rigid body for the house of `model` on the soil of `soil_params`. Checks the
/// placement (inside the soil box and outside its absorbing zone, not deeper than the mesh, clear
/// of the track's sleepers) and the mode cut-off, and refuses with the key path (ConfigError).
HouseFoundation houseFoundation(const ConfigNode& root, const building::BuildingModel& model,
                                const soil::SoilParams& soil_params);

/// The house in the soil of a scenario, when it has a house and building.coupling is two_way: returns
/// the rigid body the soil carries (the foundation, or with building.foundation.model meshed the ring
/// the house stands on) and adds a meshed foundation's concrete to soil_params.mesh.inclusions. None
/// and no change otherwise.
std::vector<soil::RigidBodySpec> attachHouse(const ConfigNode& root, soil::SoilParams& soil_params);

/// The soil receivers a scenario's house needs: its free-field points, and, when the house is driven by
/// this soil run (include_footprint), every footprint point (building::footprintPoints, in that order).
/// None without a `building` section. The soil node and the tools hand them to soil::loadSoilParams.
soil::HouseReceivers houseReceivers(const ConfigNode& root, bool include_footprint);

}  // namespace railvib::coupling
