// railvib/vehicle: parameters of the T2000 half-vehicle model, of the rail
// unevenness and of a passage, read from the merged configuration.
//
// Half-vehicle convention (one rail): carbody and bogie masses and pitch
// inertias are the whole-vehicle figures of the paper times
// `vehicle.half_vehicle.body_share_per_rail` (0.5 by symmetry); wheels are
// independent wheels, one per axle position and rail, so wheel masses,
// primary, ring, secondary (one element per bogie side) and Hertz constants
// are per rail as given. The soil receives both rails (2x the half track).
#pragma once

#include <string>
#include <vector>

#include "railvib/common/config.hpp"

namespace railvib::vehicle {

enum class AxleType { Motor, Trailer };

struct VehicleParams {
  // carbodies (whole vehicle figures; multiplied by body_share_per_rail)
  double end_carbody_mass_kg = 7580.0;
  double central_carbody_mass_kg = 2600.0;
  double end_carbody_pitch_inertia_kg_m2 = 5.5e4;
  double central_carbody_pitch_inertia_kg_m2 = 3.8e3;
  // bogies (whole vehicle figures)
  double bogie_mass_kg = 1800.0;
  double bogie_pitch_inertia_kg_m2 = 300.0;
  // motor wheel (per wheel): motor-wheel mass, tread on the resilient ring
  double motor_mass_kg = 945.0;
  double tread_mass_kg = 80.0;
  double ring_stiffness_n_m = 145.0e6;
  double ring_damping_n_s_m = 3.0e3;
  double motor_radius_m = 0.34;
  // trailer wheel (per wheel)
  double trailer_mass_kg = 160.0;
  double trailer_radius_m = 0.34;
  // suspensions (per wheel / per bogie side)
  double motor_primary_stiffness_n_m = 44.0e6;
  double motor_primary_damping_n_s_m = 18.0e3;
  double trailer_primary_stiffness_n_m = 5.88e6;
  double trailer_primary_damping_n_s_m = 6.0e3;
  double secondary_stiffness_n_m = 960.0e3;
  double secondary_damping_n_s_m = 56.25e3;
  // axles: offsets behind the front axle (m), strictly increasing, 2 per bogie
  std::vector<double> axle_offsets_m{0.0, 1.6667, 7.5, 9.1667, 15.0, 16.6667};
  std::vector<AxleType> axle_types{AxleType::Motor, AxleType::Trailer, AxleType::Motor,
                                   AxleType::Motor, AxleType::Trailer, AxleType::Motor};
  double hertz_constant_n_m1_5 = 1.0e11;
  // half-vehicle convention
  double body_share_per_rail = 0.5;
  // geometry (offsets behind the front axle) and articulation joint model
  std::vector<double> carbody_com_offsets_m{1.5833, 8.3333, 15.0833};
  std::vector<double> articulation_offsets_m{6.2333, 10.4333};
  /// Relative pitch stiffness/damping of each articulation (whole vehicle figures, N m/rad, N m s/rad).
  double articulation_pitch_stiffness_n_m_rad = 2.0e6;
  double articulation_pitch_damping_n_m_s_rad = 0.0;
  double gravity_m_s2 = 9.81;

  int axleCount() const { return static_cast<int>(axle_offsets_m.size()); }
  int bogieCount() const { return axleCount() / 2; }
};

/// Random track irregularity from a one-sided vertical PSD (documented in docs/vehicle.md).
struct RandomIrregularityParams {
  bool enabled = false;
  /// "fra": S(W) = k A W_c^2 / (W^2 (W^2 + W_c^2)) [m^2/(rad/m)], W in rad/m;
  /// "power_law": S(W) = A (W_ref / W)^exponent [m^2/(rad/m)].
  std::string psd = "fra";
  double fra_a_m2_rad_m = 0.0339e-4;  // A_v, FRA class 6 [public]
  double fra_cutoff_rad_m = 0.8245;   // W_c [public]
  double fra_k = 0.25;                // [public]
  double power_law_a_m3_rad = 1.0e-7;
  double power_law_ref_rad_m = 1.0;
  double power_law_exponent = 3.0;
  double min_wavelength_m = 0.5;
  double max_wavelength_m = 50.0;
  int component_count = 400;
  unsigned long seed = 1;
  /// Sampling of the precomputed profile (m).
  double grid_spacing_m = 5.0e-3;
};

struct MeasuredProfileParams {
  bool enabled = false;
  std::string file;    ///< CSV with columns x_m, z_m (z up, m)
  double scale = 1.0;  ///< multiplies z
  /// Largest |scale x z| accepted (limits.unevenness_m): a profile beyond it is refused.
  double max_abs_m = 0.1;
};

struct DefectParams {
  bool enabled = true;
  double position_m = 0.0;  ///< start of the pad (m along the track)
  double height_m = 1.0e-3;
  double length_m = 5.0e-3;
};

struct UnevennessParams {
  DefectParams defect;
  RandomIrregularityParams random;
  MeasuredProfileParams measured;
};

/// The rail the vehicle runs on in the passage (simulation.vehicle_track).
enum class VehicleTrack {
  Flexible,  ///< coupled vehicle/track solve on the track model
  Rigid,     ///< undeformable rail (the track node still turns the contact forces into ballast loads)
};

struct PassageParams {
  VehicleTrack vehicle_track = VehicleTrack::Flexible;
  double speed_m_s = 30.0 / 3.6;
  double duration_s = 5.0;
  double time_step_s = 1.0e-5;
  double front_axle_start_m = -11.666666666666666;
  /// Newton tolerance on the contact forces, relative to the mean static wheel load.
  double contact_tolerance = 1.0e-9;
  /// Flexible track: start from the static deflection convected with the
  /// moving loads (v = -V du/dx) instead of at rest. Off by default so that
  /// the track node (TrackStepper::start, at rest) reproduces the coupled run.
  bool convected_track_start = false;
};

/// Read and validate the `vehicle` section (ranges, axle order, geometry). Throws ConfigError.
VehicleParams loadVehicleParams(const ConfigNode& root);
/// Read `unevenness` (defect; optional random/measured); checks the defect lies
/// inside the modelled track (`track.extent`) when that section exists.
UnevennessParams loadUnevennessParams(const ConfigNode& root);
/// Read `simulation` (rail under the vehicle, speed, duration, time step, front axle start): the one
/// loader of that section, for every node and command that needs its values.
PassageParams loadPassageParams(const ConfigNode& root);

}  // namespace railvib::vehicle
