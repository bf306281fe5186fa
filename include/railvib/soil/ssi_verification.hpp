// railvib/soil: verification of the soil-structure interaction model (rigid_body.hpp) against
// published solutions, shared by the unit tests and `railvib_tool ssi-bench` (docs/soil.md,
// "Soil-structure interaction: verification").
//
//   footing-static     rigid massless square surface footing 2B x 2B on a homogeneous half-space:
//                      vertical and rocking static stiffness by dynamic relaxation in boxes of growing
//                      size with a fixed bottom, extrapolated to the half-space (flexibility linear in
//                      1 / box size), against Gazetas (1991) and Pais & Kausel (1988);
//   footing-impedance  the same footing under a force wavelet in a box with dashpots: K(w) = F(w)/U(w),
//                      F the load on the massless footing, against the published dynamic coefficients;
//   block              a rigid massive block on the footing: free vertical vibration after a short pulse
//                      (damped frequency, damping ratio by logarithmic decrement) against Lysmer's analog;
//   kinematic          an embedded massless rigid box in a layered soil excited by a distant surface load:
//                      the foundation's vertical velocity over the free field's, per one-third octave band.
//
// Quarter models: the footing occupies [0, B] x [0, B] at the corner of the box, with symmetry planes
// x = 0 and y = 0 (vertical) or symmetry x = 0 and antisymmetry y = 0 (rocking about the x axis).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

// ---- Published closed forms (homogeneous elastic half-space, rigid rectangular surface footing 2L x 2B,
// L >= B the half sides, x along L; "rocking about x" turns about the long axis) ----

/// Hann pulse 0.5 (1 - cos 2 pi t / T) for 0 <= t < T, else 0: the force history of the verification runs.
double hannPulse(double t_s, double duration_s);

/// Gazetas (1991), J. Geotech. Eng. 117(9), Table 1 (surface): K_z = 2 G L / (1 - nu) (0.73 + 1.54 chi^0.75),
/// chi = A_b / (4 L^2).
double gazetasVerticalStiffness(const Material& m, double l_m, double b_m);
/// Gazetas (1991): the same footing embedded D in the half-space with its side walls in contact over their
/// height: K_z (1 + D / (21 B) (1 + 1.3 chi)) (1 + 0.2 (A_w / A_b)^(2/3)), A_w the side walls' area.
double gazetasEmbeddedVerticalStiffness(const Material& m, double l_m, double b_m, double d_m);
/// Gazetas (1991): K_rx = G / (1 - nu) I_bx^0.75 (L / B)^0.25 (2.4 + 0.5 B / L), I_bx = (2L)(2B)^3 / 12.
double gazetasRockingStiffnessX(const Material& m, double l_m, double b_m);
/// Gazetas (1991): K_ry = 3 G / (1 - nu) I_by^0.75 (L / B)^0.15, I_by = (2B)(2L)^3 / 12.
double gazetasRockingStiffnessY(const Material& m, double l_m, double b_m);
/// Pais & Kausel (1988), Soil Dyn. Earthq. Eng. 7(4): K_z = G B / (1 - nu) (3.1 (L / B)^0.75 + 1.6).
double paisKauselVerticalStiffness(const Material& m, double l_m, double b_m);
/// Pais & Kausel (1988), embedded D with side-wall contact: K_z (1 + (0.25 + 0.25 B / L) (D / B)^0.8).
double paisKauselEmbeddedVerticalStiffness(const Material& m, double l_m, double b_m, double d_m);
/// Pais & Kausel (1988): K_rx = G B^3 / (1 - nu) (3.2 L / B + 0.8).
double paisKauselRockingStiffnessX(const Material& m, double l_m, double b_m);
/// Pais & Kausel (1988): K_ry = G B^3 / (1 - nu) (3.73 (L / B)^2.4 + 0.27).
double paisKauselRockingStiffnessY(const Material& m, double l_m, double b_m);

/// Dynamic vertical impedance K(w) = K_dyn + i w C of a rigid surface footing, a0 = w B / Vs.
struct VerticalImpedance {
  double stiffness_n_m = 0.0;  // K_dyn = Re K
  double dashpot_n_s_m = 0.0;  // C = Im K / w
};
/// The normalisation of both references, K(w) = K_s (k(a0) + i a0 c(a0)): k = K_dyn / K_s, c = C Vs / (K_s B).
struct DynamicCoefficients {
  double k = 0.0, c = 0.0;
};
inline DynamicCoefficients dynamicCoefficients(const VerticalImpedance& z, double k_static_n_m, double b_m,
                                               double vs_m_s) {
  return {z.stiffness_n_m / k_static_n_m, z.dashpot_n_s_m * vs_m_s / (k_static_n_m * b_m)};
}
/// Pais & Kausel (1988), in the form of NIST GCR 12-917-21 (2012), Table 2-3a:
/// K_dyn = K_z (1 - (0.4 + 0.2 B/L) a0^2 / (10 / (1 + 3 (L/B - 1)) + a0^2)),
/// C = 2 beta K_dyn / w with beta = 4 psi (L/B) / (K_z / (G B)) a0 / (2 alpha), i.e. C = psi rho Vs A,
/// psi = min(sqrt(2 (1 - nu) / (1 - 2 nu)), 2.5), A = 4 L B.
VerticalImpedance paisKauselVerticalImpedance(const Material& m, double l_m, double b_m, double a0);
/// Gazetas (1991), Table 1 charts for a square (L/B = 1, nu <= 0.4): K_dyn = K_z k_z(a0), C = rho V_La A c_z(a0),
/// V_La = 3.4 Vs / (pi (1 - nu)) (Lysmer's analog velocity); k_z and c_z interpolated linearly between
/// digitised chart values, a0 in [0, 2] (the charts' range; held at the a0 = 2 values beyond).
VerticalImpedance gazetasSquareVerticalImpedance(const Material& m, double b_m, double a0);

/// Lysmer's analog (Lysmer & Richart, J. Soil Mech. Found. Div. 92(SM1), 1966) of a rigid circular footing
/// of radius r: m u'' + C u' + K u = F with K = 4 G r / (1 - nu), C = 3.4 r^2 sqrt(G rho) / (1 - nu).
struct LysmerAnalog {
  double stiffness_n_m = 0.0, dashpot_n_s_m = 0.0;
  double mass_kg = 0.0;
  /// Mass ratio B_z = (1 - nu) m / (4 rho r^3).
  double mass_ratio = 0.0;
  double natural_hz = 0.0;     // sqrt(K / m) / (2 pi)
  double damping_ratio = 0.0;  // C / (2 sqrt(K m)) = 0.425 / sqrt(B_z)
  double damped_hz = 0.0;      // natural sqrt(1 - zeta^2): free vibration
  double resonance_hz = 0.0;   // natural sqrt(1 - 2 zeta^2): peak of the displacement under a harmonic force
};
LysmerAnalog lysmerAnalog(const Material& m, double radius_m, double mass_kg);

// ---- FE models ----

/// Richardson extrapolation of v(x) = v_0 + a x^q to x = 0 from two values (x1 != x2 > 0).
double extrapolatePower(double x1, double v1, double x2, double v2, double q);
/// The order q of v(x) = v_0 + a x^q through three values x1 > x2 > x3 > 0 (throws if they are not monotone).
double convergenceOrder(double x1, double v1, double x2, double v2, double x3, double v3);
/// Value at h = 0 of a quantity whose discretisation error is linear in the element size h (a rigid footing's
/// edge: the stress singularity makes the stiffness error O(h)), from two meshes.
inline double extrapolateToZeroSize(double h_coarse, double v_coarse, double h_fine, double v_fine) {
  return extrapolatePower(h_coarse, v_coarse, h_fine, v_fine, 1.0);
}

/// Quarter model of a rigid massless square surface footing 2B x 2B on a homogeneous half-space: cubes of
/// side h, box [0, box] x [0, box] x [0, box] (box = the half width and the depth).
struct FootingModelSpec {
  Material material{5.333333333333333e7, 2000.0, 1.0 / 3.0};  // Vs = 100 m/s, Vp = 200 m/s
  double half_width_m = 1.0;                                  // B
  double h_m = 0.125;
  Precision precision = Precision::Double;
  int threads = 0;
  /// Embedment depth D (m, a multiple of h; 0: a surface footing). The foundation is rigid (the soil nodes of
  /// [0, B]^2 x [0, D] carried by the body), or `meshed`: a closed concrete box whose top slab, walls and base
  /// slab are `wall_m` thick (a multiple of h; 0: one element), implicit soil inclusions (implicit_unit.hpp),
  /// soil inside, the body carrying its top face.
  double embedment_m = 0.0;
  bool meshed = false;
  double wall_m = 0.0;
  Material concrete{20.0e9, 2400.0, 0.2};
  /// The concrete's stiffness-proportional damping (s): the house's, 2 % at 10 and 50 Hz
  /// (config/building_house.yaml).
  double concrete_beta_s = 1.06e-4;
};

enum class FootingMode { Vertical, Rocking };

struct StaticStiffnessRun {
  double box_m = 0.0;
  double stiffness = 0.0;  // full footing: N/m (vertical) or N m/rad (rocking)
  double residual = 0.0;   // |generalised force on the footing| / load at the end
  uint64_t steps = 0;
  size_t elements = 0;
  double seconds = 0.0;
};
struct StaticStiffnessResult {
  FootingMode mode = FootingMode::Vertical;
  double h_m = 0.0;
  std::vector<StaticStiffnessRun> runs;  // one per box, in the order given (increasing)
  /// Half-space stiffness from the flexibilities f(R) of the three largest boxes: f(R) = f_inf + a R^-p, p
  /// fitted (a vertical force's far field decays as 1 / R, so p ~ 1 is expected for the vertical mode).
  double extrapolated = 0.0, exponent = 0.0;
  /// The same with p = 1 through the two largest boxes (its difference to `extrapolated`: the uncertainty).
  double extrapolated_inverse_r = 0.0;
  /// Unit of the normalised values: G B / (1 - nu) (vertical) or G B^3 / (1 - nu) (rocking).
  double unit = 0.0;
};
/// Static stiffness in one box by dynamic relaxation (mass-proportional damping 2 w_1, w_1 = pi Vs / (2 box)),
/// fixed bottom, free sides, until the footing's displacement changes by less than `tolerance` (relative) over
/// a quarter of 1 / w_1 and the force left on it is below 10 x tolerance of the load.
StaticStiffnessRun runFootingStaticBox(const FootingModelSpec& spec, FootingMode mode, double box_m,
                                       double tolerance = 1e-6);
/// The same in each box (at least three, increasing) and the extrapolation to the half-space.
StaticStiffnessResult runFootingStatic(const FootingModelSpec& spec, FootingMode mode,
                                       const std::vector<double>& boxes_m, double tolerance = 1e-6);

struct ImpedanceSpec {
  FootingModelSpec footing;
  double box_m = 8.0;
  /// Duration T of the force wavelet, one sine cycle under a Hann window (0: 1 / f(a0_max)).
  double pulse_s = 0.0;
  /// Analysis window (0: 2 box / Vp, before a P wave reflected by the bottom is back).
  double window_s = 0.0;
  /// Dimensionless frequencies, increasing (the two lowest give the static limit).
  std::vector<double> a0 = {0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5};
};
struct ImpedancePoint {
  double a0 = 0.0, frequency_hz = 0.0;
  VerticalImpedance fe, gazetas, pais_kausel;
};
struct ImpedanceResult {
  std::vector<ImpedancePoint> points;
  double pulse_s = 0.0, window_s = 0.0, dt_s = 0.0;
  uint64_t steps = 0;
  size_t elements = 0;
  double seconds = 0.0;
  /// Static stiffness: the low-frequency limit K_s of K_dyn = K_s - m a0^2 through the two lowest a0.
  double static_stiffness_n_m = 0.0;
  /// Units of the normalised values: G B / (1 - nu) for K_dyn and rho Vs A for C.
  double stiffness_unit = 0.0, dashpot_unit = 0.0;
  /// |displacement| at the end of the window / its peak: the footing must be back at rest.
  double end_displacement = 0.0;
  /// Full footing: t_n, U(t_n), the load and the force of the soil elements on the carried nodes.
  std::vector<double> t_s, displacement_m, load_n, soil_force_n;
};
ImpedanceResult runFootingImpedance(const ImpedanceSpec& spec);

struct BlockSpec {
  FootingModelSpec footing;
  double box_m = 16.0;
  /// Lysmer's mass ratio B_z of the block (whole mass, carried soil nodes included), r = 2B / sqrt(pi).
  double mass_ratio = 5.0;
  /// Hann force pulse (0: a tenth of the analog's natural period).
  double pulse_s = 0.0;
  /// Run length (0: until a shear wave reflected by a side face is back, 2 (box - B) / Vs).
  double duration_s = 0.0;
};
struct BlockResult {
  LysmerAnalog lysmer;
  double equivalent_radius_m = 0.0;
  /// Free vibration after the pulse: damped frequency from the zero crossings, damping ratio from the
  /// logarithmic decrement of successive extrema (those above 2 % of the first).
  double damped_hz = 0.0, damping_ratio = 0.0;
  int extrema_used = 0;
  /// Peak of |U(f) / F(f)| over [0.3, 2] x the analog's natural frequency.
  double resonance_hz = 0.0;
  double dt_s = 0.0;
  uint64_t steps = 0;
  size_t elements = 0;
  double seconds = 0.0;
  std::vector<double> t_s, displacement_m;
};
BlockResult runBlock(const BlockSpec& spec);

/// Kinematic interaction: half model (symmetry x = 0) of a layered soil with a massless rigid box foundation
/// embedded `foundation_depth_m`, excited by a vertical Hann pulse point load on the surface at (0, load_y);
/// the run is repeated without the foundation (free field).
struct KinematicSpec {
  std::vector<Layer> profile;  // layers then the half-space
  double f_max_hz = 50.0, elements_per_wavelength = 8.0;
  /// Rayleigh damping, boundary, precision and threads (the absorbing x_min face becomes the symmetry plane).
  SolverOptions solver;
  double x_max_m = 25.0, y_min_m = -13.0, y_max_m = 26.0, depth_m = 22.0;
  /// Foundation (frame track: x along, y away from the track): x in [-foundation_half_length, +...].
  double foundation_half_length_m = 5.0;
  double foundation_y_min_m = 4.7175, foundation_y_max_m = 11.7175;
  double foundation_depth_m = 0.85;
  /// Body mass as a fraction of the soil mass it carries (the rigid region); small = massless.
  double mass_fraction = 0.2;
  double load_y_m = 0.0;
  double pulse_s = 0.02;
  double duration_s = 0.8;
  double output_rate_hz = 1000.0;
  double band_min_hz = 10.0, band_max_hz = 50.0;
};
struct KinematicBand {
  double nominal_hz = 0.0;
  /// Foundation / free field vertical velocity, rms in the band, both at the foundation's centre; and the
  /// foundation over the free field averaged over the foundation's footprint (surface nodes).
  double ratio_centre = 0.0, ratio_footprint = 0.0;
  double level_free_field_db = 0.0, level_foundation_db = 0.0;  // re 1e-9 m/s
};
struct KinematicResult {
  std::vector<KinematicBand> bands;
  /// Region of the foundation as snapped to the mesh (frame track), its carried soil mass and the body mass (half
  /// model).
  double x_max_m = 0.0, y_min_m = 0.0, y_max_m = 0.0, depth_m = 0.0;
  double carried_soil_mass_kg = 0.0, body_mass_kg = 0.0;
  double hx_m = 0.0, hy_m = 0.0, dt_s = 0.0;
  size_t elements = 0;
  uint64_t steps = 0;
  double seconds_free_field = 0.0, seconds_foundation = 0.0;
  /// Energy of the last 10 % of each record relative to its total (the record must have decayed).
  double tail_energy_free_field = 0.0, tail_energy_foundation = 0.0;
  std::vector<double> t_s, v_free_field_m_s, v_foundation_m_s, v_free_field_footprint_m_s;  // at output_rate_hz
};
KinematicResult runKinematic(const KinematicSpec& spec);

}  // namespace railvib::soil
