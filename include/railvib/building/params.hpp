// railvib/building: parameters of the house model (section `building`, placement from `site`).
//
// Building frame: origin at the outer corner of the front wall on the ground
// surface, x along the length (parallel to the track, same direction as the
// track x), y across the width away from the track, z up. Its axes are
// parallel to the `track` frame: a vector has the same components in both.
#pragma once

#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/common/site.hpp"

namespace railvib::building {

/// Isotropic linear-elastic material of a shell section.
struct ShellMaterial {
  double young_modulus_pa = 0.0;
  double shear_modulus_pa = 0.0;
  double density_kg_m3 = 0.0;
  /// nu = E / (2 G) - 1.
  double poisson() const { return young_modulus_pa / (2.0 * shear_modulus_pa) - 1.0; }
};

/// A named point where velocities are output (here in the building frame).
using NamedPoint = railvib::NamedPoint;

/// A rectangular opening (window, door) cut into an exterior wall.
struct Opening {
  std::string wall;       ///< front | back | left | right
  double start_m = 0.0;   ///< along the wall, from its low-x (front/back) or low-y (left/right) end
  double bottom_m = 0.0;  ///< above the ground surface (z)
  double width_m = 0.0;
  double height_m = 0.0;
};

/// A full-height interior masonry wall (same section as the exterior walls), snapped to the nearest mesh line.
struct InteriorWall {
  std::string along;        ///< x: runs along the length at y = position_m; y: across the width at x = position_m
  double position_m = 0.0;  ///< building frame
};

/// How the house and the soil interact.
enum class SoilCoupling {
  /// The foundation follows the free-field motion of the soil at its footprint (bilinear in plan).
  OneWay,
  /// The foundation is a rigid body in the soil that carries the house (reduced) and acts back on the
  /// soil; the house follows the foundation's rigid motion, fitted from the footprint receivers.
  TwoWay,
};

/// How the two-way coupling models the foundation box in the soil.
enum class FoundationModel {
  /// The soil nodes inside the box move as one rigid body (the box's concrete added to their mass).
  Rigid,
  /// The box's walls, base slab and ground slab are concrete elements of the soil mesh (implicit soil
  /// inclusions) and the house stands, on a rigid interface, on the tops of its walls.
  Meshed,
};

struct BuildingParams {
  // Geometry [paper]: outer plan dimensions and height above the ground surface.
  double length_m = 10.0;
  double width_m = 7.0;
  double height_m = 5.0;
  int storeys = 2;
  bool roof_slab = false;  ///< [assumed] top slab at z = height

  double wall_thickness_m = 0.25;
  ShellMaterial wall;
  double floor_thickness_m = 0.20;
  ShellMaterial floor;

  double foundation_depth_m = 0.85;
  ShellMaterial foundation;
  double foundation_wall_thickness_m = 0.25;                  ///< [assumed]
  double base_slab_thickness_m = 0.25;                        ///< [assumed]
  bool ground_slab_on_fill = true;                            ///< [assumed] ground slab follows the foundation
  FoundationModel foundation_model = FoundationModel::Rigid;  ///< two_way only

  double element_size_m = 0.5;
  double damping_ratio = 0.02;  ///< [assumed] Rayleigh damping
  double damping_f1_hz = 5.0;
  double damping_f2_hz = 50.0;
  double max_time_step_s = 1.0e-3;

  SoilCoupling coupling = SoilCoupling::OneWay;
  /// two_way: fixed-interface modes kept in the reduction (Hz; 0 = twice the soil's f_max).
  double coupling_modes_max_hz = 0.0;

  int footprint_nx = 21;
  int footprint_ny = 15;
  std::vector<NamedPoint> response_points;
  std::vector<Opening> openings;
  std::vector<InteriorWall> interior_walls;  ///< [assumed] none by default

  /// Placement in the track frame (loadBuildingPlacement: site.building; length_m and width_m above
  /// are its plan, read there once).
  BuildingPlacement placement;
};

/// Load and validate `building` (and, if present, `site` for the placement).
/// Throws ConfigError with the key path on any invalid or inconsistent value.
BuildingParams loadBuildingParams(const ConfigNode& root);

/// Rayleigh damping C = alpha M + beta K with damping_ratio at damping_f1_hz and damping_f2_hz
/// (Chopra, Dynamics of Structures, 11.4): alpha 1/s, beta s.
struct RayleighCoefficients {
  double alpha_1_s = 0.0, beta_s = 0.0;
};
RayleighCoefficients rayleighCoefficients(const BuildingParams& params);

}  // namespace railvib::building
