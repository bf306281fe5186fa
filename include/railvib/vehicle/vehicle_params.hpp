// railvib/vehicle: a rail vehicle as data (bodies, suspensions per stage,
// joints, wheels), the rail unevenness and a passage, read from the merged
// configuration.
//
// The scenario names its vehicle (`vehicle.name`), an entry of the library
// `vehicles.<name>` (config/vehicle_<name>.yaml, docs/vehicle.md):
//   bodies              rigid bodies: kind, centre of mass (x behind the front
//                       axle, y lateral), mass, pitch (and roll) inertia,
//                       longitudinal extent
//   suspension_stages   the spring-damper of each stage (per element)
//   suspensions         elements: stage, upper and lower body, point (x, y)
//   joints              articulations between bodies (vertical pins)
//   wheels              the contact points: body, motor | trailer, radius
// Every body and element lies on the vehicle's centre line (y = 0: it spans
// both rails) or on one side (y > 0, listed once, its mirror image at -y: a
// symmetric vehicle). The vehicle has the track's width (`track.width`, one
// switch for the chain): the half vehicle runs on one rail, the elements and
// bodies of that side count once, those on the centre line with
// `vehicle.half_vehicle.body_share_per_rail` (0.5), and the soil receives both
// rails (2x the half track); the full-width vehicle has both sides (the side
// parts mirrored to -y, one wheel per rail per axle) and gives every
// centre-line body a roll DOF (docs/vehicle.md, "Full width").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"

namespace railvib::vehicle {

enum class AxleType { Motor, Trailer };

/// What a body is: sets its DOFs (carbodies and bogies bounce and pitch, the
/// others are point bodies that bounce), its mode names and how it is drawn.
enum class BodyKind {
  Carbody,   ///< carbody section
  Bogie,     ///< bogie frame
  WheelHub,  ///< unsprung mass above a resilient element (e.g. the T2000 hub motor wheel)
  Tread,     ///< contact body of a resilient wheel, on its resilient element
  Wheel,     ///< solid wheel or wheelset carrying the contact, directly on the primary suspension
};

struct BodySpec {
  std::string name;
  BodyKind kind = BodyKind::Carbody;
  /// Centre of mass (the body's reference point), behind the front axle (m).
  double x_m = 0.0;
  /// Lateral position of the centre of mass (m): 0 = on the centre line, > 0 = a body of one side.
  double y_m = 0.0;
  double mass_kg = 0.0;
  /// About the lateral axis through the centre of mass; carbodies and bogies only (kg m^2).
  double pitch_inertia_kg_m2 = 0.0;
  /// About the longitudinal axis through the centre of mass (kg m^2): centre-line bodies of the
  /// full-width vehicle (required there); not used by the half vehicle; a body of one side has none.
  double roll_inertia_kg_m2 = 0.0;
  /// Longitudinal extent, offsets behind the front axle (m); a point body: [x_m, x_m].
  double front_m = 0.0;
  double rear_m = 0.0;
  bool hasPitch() const { return kind == BodyKind::Carbody || kind == BodyKind::Bogie; }
  bool onCentreLine() const { return y_m == 0.0; }
};

/// A vertical spring-damper between two bodies, attached at the same point of both.
struct SuspensionSpec {
  std::string stage;  ///< e.g. primary, secondary, resilient_ring
  int upper_body = -1;
  int lower_body = -1;
  double x_m = 0.0;  ///< behind the front axle
  double y_m = 0.0;  ///< lateral: 0 = centre line, > 0 = one side (mirrored)
  double stiffness_n_m = 0.0;
  double damping_n_s_m = 0.0;
};

enum class JointType {
  VerticalPin,  ///< both bodies have the same vertical displacement at the pin; relative pitch restrained by a spring
                ///< (full width: relative roll free but for an optional roll spring)
};

struct JointSpec {
  std::string name;
  JointType type = JointType::VerticalPin;
  int body_a = -1;  ///< its vertical displacement at the pin is kept
  int body_b = -1;  ///< its bounce follows body_a's at the pin (eliminated)
  double x_m = 0.0;
  double y_m = 0.0;
  double pitch_stiffness_n_m_rad = 0.0;
  double pitch_damping_n_m_s_rad = 0.0;
  /// Full width: relative roll of the two bodies (a pin on the centre line leaves it free); optional, 0.
  double roll_stiffness_n_m_rad = 0.0;
  double roll_damping_n_m_s_rad = 0.0;
};

struct WheelSpec {
  std::string name;  ///< e.g. axle0
  int body = -1;     ///< the body carrying the contact (Tread or Wheel)
  AxleType type = AxleType::Motor;
  double radius_m = 0.34;
};

/// The wheels a resilient-wheels measure acts on (`vehicles.<name>.resilient_wheels.wheels`).
enum class ResilientWheelSet {
  Rigid,      ///< every rigid wheel carrying a contact becomes a hub and a tread on a resilient ring
  Resilient,  ///< the rings of the wheels that already have one get the section's stiffness and damping
  All,        ///< both
};

/// Resilient wheels, a source-side mitigation measure (issue 33; docs/vehicle.md, "Resilient wheels"),
/// `vehicles.<name>.resilient_wheels`. A rigid wheel body of mass m carrying a contact becomes a hub
/// (kind wheel_hub, m - n m_t, n treads: 1 for a wheel of one side, 2 for a centre-line wheelset) and
/// a tread of mass m_t per rail (kind tread, named `<wheel>_tread`, at the rail's lateral position)
/// hung from it by a resilient ring (stage `resilient_wheel`); the contact moves to the tread.
struct ResilientWheelParams {
  ResilientWheelSet wheels = ResilientWheelSet::Rigid;
  /// Tread (tyre) of a wheel made resilient, per tread (kg); 0 with `wheels: resilient`.
  double tread_mass_kg = 0.0;
  /// Resilient ring, radial, per wheel (N/m and N s/m): the ring of every wheel the measure acts on.
  double stiffness_n_m = 0.0;
  double damping_n_s_m = 0.0;
};

/// Stage name of the rings the measure adds.
inline constexpr const char* kResilientWheelStage = "resilient_wheel";
/// Radial stiffness of a resilient ring (N/m): the paper's T2000 ring is 145 MN/m. Below 10 MN/m a
/// 30-60 kN wheel load would deflect the ring by 3-6 mm, more than the rubber of a resilient wheel
/// is built to take; above 5 GN/m the ring is five times stiffer than the Hertz contact (~1 GN/m,
/// docs/vehicle.md section 2) and isolates nothing: no resilient wheel [assumed bounds].
constexpr Range kResilientRingStiffnessNM{1.0e7, 5.0e9, false, false};
/// Ring damping (N s/m): the paper's 3 kN s/m is a damping ratio of 0.014 for the 80 kg tread on
/// 145 MN/m; 1e6 N s/m would be ~5 times critical for it, beyond any elastomer [assumed bound].
constexpr Range kResilientRingDampingNSM{0.0, 1.0e6, false, false};

struct VehicleParams {
  /// Key of the vehicle in `vehicles` and its description.
  std::string name = "t2000";
  std::string description;
  std::vector<BodySpec> bodies;
  std::vector<SuspensionSpec> suspensions;
  std::vector<JointSpec> joints;
  /// Front to rear: wheel 0 is the front axle (x = 0).
  std::vector<WheelSpec> wheels;
  double hertz_constant_n_m1_5 = 1.0e11;
  /// Half (one rail, the symmetric special case) or full width (both rails, roll): track.width.
  track::TrackWidth width = track::TrackWidth::Half;
  /// Lateral position of the rails (m): half the gauge (site.rail_gauge_m), where the track's rail
  /// seats are; the contacts of a centre-line wheelset lie at +-this.
  double rail_offset_m = 0.7175;
  /// Half width: share of a centre-line body or element carried by the modelled rail.
  double body_share_per_rail = 0.5;
  double gravity_m_s2 = 9.81;
  /// The resilient-wheels measure applied to the file's vehicle (absent or disabled: none).
  std::optional<ResilientWheelParams> resilient_wheels;

  bool fullWidth() const { return width == track::TrackWidth::Full; }
  /// Axle positions (wheels of the file); the full-width model has a wheel per rail on each.
  int axleCount() const { return static_cast<int>(wheels.size()); }
  /// Axle (wheel) positions behind the front axle (m), front to rear.
  std::vector<double> axleOffsets() const;
  /// Index of the body called `name`, or -1.
  int bodyIndex(const std::string& name) const;
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
  /// Full width: the right rail's profile has the same PSD and, with the left rail's, the coherence
  /// gamma(W) = coherence exp(-coherence_decay_m_rad W) (docs/vehicle.md, "Unevenness per rail");
  /// coherence 1 and decay 0: both rails alike. Read and unused at half width (one rail).
  double coherence = 1.0;
  double coherence_decay_m_rad = 0.0;
};

struct MeasuredProfileParams {
  bool enabled = false;
  /// CSV with columns x_m and z_m (z up, m; both rails alike) or, full width only, z_left_m and
  /// z_right_m (one profile per rail).
  std::string file;
  double scale = 1.0;  ///< multiplies z
  /// Largest |scale x z| accepted (limits.unevenness_m): a profile beyond it is refused.
  double max_abs_m = 0.1;
};

/// The rails a local defect lies on (unevenness.defect.rails).
enum class DefectRails { Left, Right, Both };

struct DefectParams {
  bool enabled = true;
  /// Both (the half track's symmetric special case, its only choice) or one rail (full width).
  DefectRails rails = DefectRails::Both;
  double position_m = 0.0;  ///< start of the pad (m along the track)
  double height_m = 1.0e-3;
  double length_m = 5.0e-3;
};

struct UnevennessParams {
  DefectParams defect;
  RandomIrregularityParams random;
  MeasuredProfileParams measured;
  /// The track's width (track.width): the rails that exist.
  track::TrackWidth width = track::TrackWidth::Half;
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

/// A body or element of one side lies at most this far from the centre line (m): beyond it a
/// lateral position is a slip (7.175 for 0.7175), not a design (docs/vehicle.md, "Full width").
constexpr double kMaxSideOffsetM = 1.7;
/// A side body carrying a wheel stands on its rail: |y - rail_offset_m| within this (m).
constexpr double kWheelOnRailToleranceM = 1.0e-3;

/// Read and validate the scenario's vehicle: `vehicle` (which entry of `vehicles`, the half-vehicle
/// share, gravity), its width (the track's: track.width, rails at +-site.rail_gauge_m / 2) and that
/// entry. Refuses, with key path, value and file: unknown bodies, negative masses, elements or wheels
/// outside their bodies, wheels out of order or off their rail, lateral positions beyond
/// kMaxSideOffsetM, bodies connected to no wheel, a full-width vehicle without the roll inertia of a
/// centre-line body, a mechanism (a motion no spring resists: docs/vehicle.md). Applies the entry's
/// optional `resilient_wheels` measure (ResilientWheelParams), refusing a tread mass not below the
/// wheel's (a wheelset: half its), a ring stiffness outside kResilientRingStiffnessNM, a measure that
/// changes nothing. Throws ConfigError.
VehicleParams loadVehicleParams(const ConfigNode& root);
/// The same for the library entry `vehicles.<name>`, whatever `vehicle.name` says.
VehicleParams loadVehicleParams(const ConfigNode& root, const std::string& name);
/// Names of the vehicles in the library `vehicles`, in file order.
std::vector<std::string> vehicleLibrary(const ConfigNode& root);
/// Read `unevenness` (defect; optional random/measured); checks the defect lies
/// inside the modelled track (`track.extent`) when that section exists, and refuses a defect on one
/// rail of the half track (its one rail stands for both: the symmetric special case).
UnevennessParams loadUnevennessParams(const ConfigNode& root);
/// Read `simulation` (rail under the vehicle, speed, duration, time step, front axle start): the one
/// loader of that section, for every node and command that needs its values.
PassageParams loadPassageParams(const ConfigNode& root);

}  // namespace railvib::vehicle
