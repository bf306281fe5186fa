// railvib/track: flexible track (one rail = half track, or both rails: track.width) on discrete supports.
//
// Rail: Euler-Bernoulli beam, Hermite cubic elements (w, theta per node),
// `elements_per_bay` elements between sleepers. Under each sleeper node:
// railpad spring/dashpot rail -> sleeper mass, ballast spring/dashpot
// sleeper -> foundation. Foundation models:
//   clm     per sleeper a mass m_f, k_f/d_f to ground, k_c/d_c to the
//           neighbouring foundation masses (d_c may be negative);
//   winkler no foundation mass: the ballast is in series with the equivalent
//           Winkler spring k_f = k_b / ratio and a damper d_f to ground. The
//           series junction is a MASSLESS node (a DOF with zero mass): exact
//           series combination in the frequency domain, a first-order
//           relaxation in the time domain (integrated by the same Newmark
//           scheme; K_eff stays SPD because K is SPD);
//   rigid   ballast to a fixed ground (verification model).
//
// Conventions: x along the track (m); vertical displacements positive
// DOWNWARD, loads positive downward (contact force in compression pushes the
// rail down). Rail slope theta = dw/dx (w downward).
//
// Ballast-to-soil load of sleeper i (half track, N, positive downward):
//   f_i = k_b (u_sleeper - u_base) + d_b (v_sleeper - v_base),
// the force the ballast spring/dashpot puts on the foundation (base = CLM
// foundation mass, Winkler massless node, or fixed ground). In the Winkler
// case it equals the force transmitted to the ground (massless node). The
// soil receives both rails: 2 f_i. The track's own dead weight is not
// included (linear model, loads from the vehicle only).
//
// Resilient layers (optional, track.under_sleeper_pad / track.under_ballast_mat): an under-sleeper
// pad (USP) between the sleeper and the ballast, an under-ballast mat (UBM) between the ballast and
// the foundation (CLM mass, Winkler node or fixed ground). Each is a spring k = C_bed A (bedding
// modulus over its bearing area per rail seat) with a viscous damper d = eta k / (2 pi f_ref) that
// matches the layer's hysteretic loss factor eta at the reference frequency f_ref, in series with
// the ballast through a MASSLESS node (as the Winkler junction). Seat chain, top to bottom:
//   rail -(railpad)- seat -(USP)- pad node -(ballast)- mat node -(UBM)- base.
// With a UBM the foundation (and the soil) receives the mat's force (ballastForceOnFoundation).
//
// Full width (TrackWidth::Full): both rails, each sleeper a rigid body with heave and roll (the seat
// at lateral y moves down by heave + y roll), railpad, ballast and foundation chain under each rail
// seat; the half track is its symmetric special case (docs/track.md, "Full width").
//
// Track ends: the rail is free at the first/last sleeper; over
// `ends.absorbing_length_m` at each end a mass-proportional damping layer
// C_abs = eta(x) M (rail consistent mass, sleeper and foundation masses) with
// eta(x) = eta_max (d/L_abs)^2 (d = depth into the layer) absorbs outgoing
// bending and foundation waves. It is velocity-proportional to ground only,
// so statics are unaffected. See docs/track.md for the measured reflection.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/common/site.hpp"

namespace railvib::track {

enum class FoundationModel { Clm, Winkler, Rigid };

std::string foundationName(FoundationModel model);

/// How much of the track is modelled (track.width): half = one rail on half sleepers (the
/// symmetric special case); full = both rails on whole sleepers with heave and roll.
enum class TrackWidth { Half, Full };

/// The rails of a full-width track, looking in the direction of travel (+x): left at y = +a (the
/// side of the building), right at y = -a, a = rail_gauge_m / 2.
enum class Rail { Left = 0, Right = 1 };

/// Which rails a harmonic or static load acts on (receptance --load): one rail, both in phase, or
/// both in anti-phase (left down, right up).
enum class RailLoading { Left, Right, Both, AntiPhase };

/// The soil under a half track receives both rails: the ballast force of the modelled rail seat
/// times this (the symmetric special case of the full width: both rails load each footprint alike).
constexpr double kHalfTrackRailsOnSoil = 2.0;

struct ClmParams {
  double mass_kg = 2502.0;
  double stiffness_n_m = 30.0e6;
  double damping_n_s_m = 150.0e3;
  double coupling_stiffness_n_m = 41.0e6;
  double coupling_damping_n_s_m = -23.0e3;
};

struct WinklerParams {
  /// Equivalent Winkler foundation stiffness per sleeper, k_f = k_b / ratio.
  double stiffness_n_m = 32.0e6 / 0.26;
  double damping_n_s_m = 150.0e3;
};

/// A resilient layer of the support (under-sleeper pad, under-ballast mat) as manufacturers quote
/// it: a bedding modulus (EN 16730 for USPs, DIN 45673-5 for UBMs) over a bearing area, and a
/// hysteretic loss factor. The time-domain (Newmark) model needs a viscous damper: d = eta k / w_ref
/// gives the layer's loss factor eta at f_ref exactly (eta f / f_ref at f; the same damper is used in
/// the frequency domain, so both domains describe one model).
struct ResilientLayer {
  /// Bedding modulus C_bed (N/mm^3): pressure per unit compression of the layer.
  double bedding_modulus_n_mm3 = 0.1;
  /// Bearing area per rail seat (m^2) over which the layer carries the load.
  double bearing_area_m2 = 0.325;
  /// Hysteretic loss factor eta (-) of the layer material.
  double loss_factor = 0.1;
  /// Frequency (Hz) at which the viscous damper matches the loss factor.
  double reference_frequency_hz = 50.0;

  /// Spring per rail seat (N/m): C_bed (1e9 N/m^3 per N/mm^3) x area.
  double stiffnessNPerM() const { return bedding_modulus_n_mm3 * 1.0e9 * bearing_area_m2; }
  /// Equivalent viscous damper per rail seat (N s/m): eta k / (2 pi f_ref).
  double dampingNsPerM() const { return loss_factor * stiffnessNPerM() / (2.0 * M_PI * reference_frequency_hz); }
};

struct EndParams {
  /// Length of the damping layer at each end (0 = no layer).
  double absorbing_length_m = 12.0;
  /// Maximum mass-proportional damping rate eta_max (1/s) at the very end.
  double max_damping_rate_1_s = 300.0;
};

struct TrackParams {
  // rail
  double rail_bending_stiffness_n_m2 = 4.17e6;
  double rail_mass_per_length_kg_m = 54.0;
  int elements_per_bay = 4;
  /// Sleepers (at x = offset + k * spacing inside the extent [x_min, x_max]) and their footprint.
  TrackLayout layout;
  /// Sleeper mass per rail seat: the half track's sleeper; a full-width sleeper weighs twice this.
  double sleeper_mass_kg = 45.0;
  TrackWidth width = TrackWidth::Half;
  /// Full width: the whole sleeper's roll inertia about the track axis (kg m^2) and the rail seats'
  /// lateral distance from the track axis (m, half the gauge).
  double sleeper_roll_inertia_kg_m2 = 50.7;
  double rail_seat_offset_m = 0.7175;
  // railpad, ballast (per rail seat)
  double railpad_stiffness_n_m = 90.0e6;
  double railpad_damping_n_s_m = 30.0e3;
  double ballast_stiffness_n_m = 32.0e6;
  double ballast_damping_n_s_m = 52.0e3;
  /// Resilient layers (per rail seat; absent: none, the paper's track).
  std::optional<ResilientLayer> under_sleeper_pad;
  std::optional<ResilientLayer> under_ballast_mat;
  // foundation (per rail seat: a full-width track has one chain under each rail)
  FoundationModel foundation = FoundationModel::Clm;
  ClmParams clm;
  WinklerParams winkler;
  EndParams ends;
  /// Rate of the ballast-to-soil loads handed to the soil (decimation target).
  double load_sample_rate_hz = 2000.0;

  /// Minimum number of sleepers a model must have.
  static constexpr int kMinSleepers = 10;
};

/// Read and validate the `track` section (ranges + consistency; the layout by loadTrackLayout).
/// Throws ConfigError.
TrackParams loadTrackParams(const ConfigNode& root);

/// The lateral positions (m, frame track; left = +y) of the rail seats whose forces the soil takes
/// one by one: none for the half track (the soil takes one force per sleeper, both rails together:
/// kHalfTrackRailsOnSoil x the seat's), {+a, -a} at full width (a = rail_seat_offset_m).
std::vector<double> soilRailSeatPositions(const TrackParams& params);

/// The soil's load frames from ballast forces per rail seat, seat-major per sample ([sample][seat]
/// [sleeper]: TrackNewmark::ballastForcesPerSeat, PassageBlock::ballast_force_n): one seat (the half
/// track) gives kHalfTrackRailsOnSoil x the seat per sleeper; two give [sample][sleeper][seat], the
/// order soil::SoilModel takes. `out` is replaced; sizes are checked (std::invalid_argument).
void soilLoadFrames(const std::vector<double>& ballast_seat_major_n, size_t sleepers, size_t seats,
                    std::vector<double>& out_n);

/// A position on the rail: the 4 DOFs of the Hermite element holding it and
/// the shape-function weights. Rail displacement w(x) = sum weights[k] * u[dofs[k]],
/// slope dw/dx = sum slope_weights[k] * u[dofs[k]]. A unit point load at x has
/// the consistent nodal load vector r with r[dofs[k]] = weights[k].
struct RailPoint {
  double x_m = 0.0;
  std::array<Eigen::Index, 4> dofs{};
  std::array<double, 4> weights{};
  std::array<double, 4> slope_weights{};

  double displacement(const Eigen::VectorXd& u) const {
    return weights[0] * u[dofs[0]] + weights[1] * u[dofs[1]] + weights[2] * u[dofs[2]] + weights[3] * u[dofs[3]];
  }
  double slope(const Eigen::VectorXd& u) const {
    return slope_weights[0] * u[dofs[0]] + slope_weights[1] * u[dofs[1]] + slope_weights[2] * u[dofs[2]] +
           slope_weights[3] * u[dofs[3]];
  }
  /// f += force * r (consistent nodal load of a point load).
  void addLoad(double force_n, Eigen::VectorXd& f) const {
    for (int k = 0; k < 4; ++k) f[dofs[k]] += force_n * weights[k];
  }
};

/// A vertical point load on a rail (N, positive downward); the half track has the left rail only.
struct PointLoad {
  double x_m = 0.0;
  double force_n = 0.0;
  Rail rail = Rail::Left;
};

/// Assembled matrices of one rail on its supports.
class TrackModel {
 public:
  explicit TrackModel(const TrackParams& params);

  const TrackParams& params() const { return params_; }
  Eigen::Index dofCount() const { return n_dof_; }
  const Eigen::SparseMatrix<double>& mass() const { return M_; }
  const Eigen::SparseMatrix<double>& damping() const { return C_; }
  const Eigen::SparseMatrix<double>& stiffness() const { return K_; }

  int sleeperCount() const { return static_cast<int>(sleeper_x_.size()); }
  const std::vector<double>& sleeperPositions() const { return sleeper_x_; }
  /// Index of the sleeper nearest x (m); the first of two at the same distance.
  int nearestSleeper(double x_m) const;
  int railNodeCount() const { return static_cast<int>(node_x_.size()); }
  const std::vector<double>& railNodePositions() const { return node_x_; }
  double railStart() const { return node_x_.front(); }
  double railEnd() const { return node_x_.back(); }
  /// Positions inside the damping layers are "absorbing"; loads should stay out of them.
  double interiorStart() const { return railStart() + params_.ends.absorbing_length_m; }
  double interiorEnd() const { return railEnd() - params_.ends.absorbing_length_m; }

  /// Rails modelled: 1 (half track, the left rail) or 2 (full width).
  int railCount() const { return rails_; }
  /// Lateral position of a rail's seat on the sleeper (m, frame track; 0 for the half track).
  double railSeatY(Rail rail) const;

  /// DOF indices: rail deflection / rotation of node j, sleeper i's heave (and, full width, roll:
  /// the seat at lateral y moves down by heave + y roll), the base under each rail seat of sleeper i
  /// (foundation mass or Winkler massless node; -1 for the rigid model).
  Eigen::Index railW(int node, Rail rail = Rail::Left) const { return rail_dof_[seatIndex(rail)][node]; }
  Eigen::Index railTheta(int node, Rail rail = Rail::Left) const { return railW(node, rail) + 1; }
  Eigen::Index sleeperDof(int sleeper) const { return sleeper_dof_[sleeper]; }
  Eigen::Index sleeperRollDof(int sleeper) const { return roll_dof_[sleeper]; }
  Eigen::Index baseDof(int sleeper, Rail rail = Rail::Left) const { return base_dof_[seatIndex(rail)][sleeper]; }
  /// The massless node between an under-sleeper pad and the ballast (the ballast's top), and between
  /// the ballast and an under-ballast mat (the ballast's bottom), under each rail seat; -1 without
  /// the layer.
  Eigen::Index padDof(int sleeper, Rail rail = Rail::Left) const { return pad_dof_[seatIndex(rail)][sleeper]; }
  Eigen::Index matDof(int sleeper, Rail rail = Rail::Left) const { return mat_dof_[seatIndex(rail)][sleeper]; }
  /// Rail node index of sleeper i.
  int sleeperNode(int sleeper) const { return sleeper * params_.elements_per_bay; }

  /// Rail interpolation at x (throws std::out_of_range outside the rail, std::invalid_argument for
  /// the right rail of a half track).
  RailPoint railPoint(double x_m, Rail rail = Rail::Left) const;
  /// Consistent load vector of point loads (size dofCount()).
  Eigen::VectorXd loadVector(const std::vector<PointLoad>& loads) const;

  /// Force on the foundation per sleeper (N, positive downward) under one rail seat (the half
  /// track's only seat by default): the ballast's, or with an under-ballast mat the mat's.
  void ballastForceOnFoundation(const Eigen::VectorXd& u, const Eigen::VectorXd& v, std::vector<double>& out,
                                Rail rail = Rail::Left) const;
  std::vector<double> ballastForceOnFoundation(const Eigen::VectorXd& u, const Eigen::VectorXd& v,
                                               Rail rail = Rail::Left) const;

  /// Static deflection K u = f under point loads.
  Eigen::VectorXd staticDeflection(const std::vector<PointLoad>& loads) const;

  /// Dynamic stiffness K - w^2 M + i w C at a frequency (w = 2 pi f); its sparsity pattern is the
  /// same at every frequency (one symbolic analysis serves a sweep).
  Eigen::SparseMatrix<std::complex<double>> dynamicStiffness(double frequency_hz) const;

  /// Direct receptance (m/N) of the rail at x: w(x) / F(x) for the harmonic
  /// load F e^{i w t}; (K - w^2 M + i w C) X = r. One sparse LU per frequency.
  std::complex<double> receptance(double x_m, double frequency_hz) const;
  std::vector<std::complex<double>> receptance(double x_m, const std::vector<double>& frequencies_hz) const;
  /// Full width: unit harmonic forces at x on the rails `loading` names (Both: 1 N on each rail in
  /// phase; AntiPhase: +1 N left, -1 N right); the deflection of the left rail at x, or of the right
  /// rail for RailLoading::Right (m per N on that rail). A half track takes Left or Both (the same).
  std::vector<std::complex<double>> receptance(double x_m, const std::vector<double>& frequencies_hz,
                                               RailLoading loading) const;

  /// Strain energy 1/2 u^T K u and kinetic energy 1/2 v^T M v (J).
  double strainEnergy(const Eigen::VectorXd& u) const;
  double kineticEnergy(const Eigen::VectorXd& v) const;

  /// Smallest eigenvalue sign check of C (false if C is indefinite, e.g. strongly negative d_c).
  bool dampingIsPositiveSemiDefinite() const;

 private:
  void build();

  size_t seatIndex(Rail rail) const;

  TrackParams params_;
  int rails_ = 1;
  Eigen::Index n_dof_ = 0;
  std::vector<double> node_x_;
  std::vector<double> sleeper_x_;
  std::vector<Eigen::Index> sleeper_dof_, roll_dof_;
  std::vector<std::vector<Eigen::Index>> rail_dof_, base_dof_;  // [seat][node or sleeper]
  std::vector<std::vector<Eigen::Index>> pad_dof_, mat_dof_;    // [seat][sleeper], -1 without the layer
  double element_length_ = 0.0;
  Eigen::SparseMatrix<double> M_, C_, K_;
};

}  // namespace railvib::track
