// railvib/coupling: the house on a very stiff soil, two-way against one-way (issue 10, docs/soil.md
// "Soil-structure interaction: verification", `railvib_tool ssi-bench stiff-soil`).
//
// As the soil stiffens, the inertial interaction (the house's inertia loading the soil under it)
// vanishes: the two-way floor responses must tend to those of the fixed-base house driven by the
// motion the foundation would have without the house. That motion is not the free field point by
// point: a rigid foundation cannot follow the differential motion of the free field over its plan
// (kinematic interaction, which does not vanish with the stiffness of the soil). The comparison
// that isolates the inertial interaction is therefore against the house driven by the rigid motion
// least-squares fitted to the free field at the footprint (the paper's "equivalent free field",
// Fig. 15); the pointwise one-way response is reported beside it as the kinematic effect.
//
// Three runs on one soil: the soil model without the house (free field), the same with the house's
// foundation and reduced superstructure attached (two-way, house_foundation.hpp); the house's
// response solver (building/response.hpp) fed by the footprint receivers of each: one-way pointwise
// and rigid fit from the free field, rigid fit from the two-way run (what the chain computes).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace railvib::coupling {

struct StiffSoilSpec {
  /// The scenario that gives the house, the track's sleepers and the soil solver's options, and the
  /// user's overrides (applied first); the check then replaces the soil by a homogeneous half-space
  /// and sets the box, the boundary (dashpots), a rigid foundation (building.foundation.model: the
  /// reference is the house on the rigid fit of the free field) and the house's distance below.
  std::string scenario_file;
  std::vector<std::string> overrides;
  double shear_wave_speed_m_s = 10000.0;
  double density_kg_m3 = 2000.0;
  double poisson_ratio = 0.25;
  /// Stiffness-proportional Rayleigh damping of the rock (s): small, so that radiation dominates.
  double rayleigh_beta_s = 1.0e-5;
  /// Plan element size (m): must divide the house's length and width (the foundation's edges on node
  /// lines). Below the foundation the levels are `level_m` thick, which sets the elements per wavelength
  /// at soil.mesh.f_max_hz (at most 100).
  double element_size_m = 1.0;
  double level_m = 2.0;
  /// The house's front wall from the rail (m): far from the load, the free field over the plan is close
  /// to a rigid motion.
  double front_wall_distance_m = 30.0;
  /// The box reaches this far beyond the house and the loaded sleeper in plan (m), and this deep.
  double margin_m = 12.0;
  double depth_m = 20.0;
  /// Vertical Hann force pulse on the sleeper nearest x = 0 (N, s).
  double force_n = 1.0e4;
  double pulse_s = 0.03;
  double duration_s = 0.5;
  int threads = 0;
};

struct StiffSoilComponent {
  /// rms over the run of the two-way response minus the reference, over the reference's rms.
  double vs_rigid_fit = 0.0;  ///< reference: house driven by the rigid fit of the free field
  double vs_one_way = 0.0;    ///< reference: house driven point by point by the free field (one_way)
  double rms_two_way_m_s = 0.0, rms_rigid_fit_m_s = 0.0;
};
struct StiffSoilPoint {
  std::string name;
  StiffSoilComponent component[3];  // vx, vy, vz up (BuildingResponseSolver's output columns)
};

struct StiffSoilResult {
  double shear_wave_speed_m_s = 0.0;
  double hx_m = 0.0, dt_s = 0.0;
  size_t elements = 0;
  uint64_t steps = 0;
  /// Foundation's rigid vertical velocity (fit at the plan centre), two-way against the rigid fit of the
  /// free field: rms of the difference over the free field fit's rms.
  double foundation_vz_vs_free_field_fit = 0.0;
  /// Share of the free field's vertical velocity over the footprint a rigid base cannot follow:
  /// rms(v - fit) / rms(v) over all footprint points and samples.
  double free_field_non_rigid_share = 0.0;
  /// The house's shell model (superstructure and foundation box, kg) and the soil the rigid body carries (kg).
  double house_mass_kg = 0.0, carried_soil_mass_kg = 0.0;
  std::vector<StiffSoilPoint> points;  // the house's response points (building.response_points)
  double seconds_free_field = 0.0, seconds_two_way = 0.0;
};

/// Runs the three cases; throws ConfigError on a bad scenario or spec.
StiffSoilResult runStiffSoilCheck(const StiffSoilSpec& spec);

}  // namespace railvib::coupling
