// railvib/soil: Lamb's problem — surface vertical displacement of a
// homogeneous elastic half-space under a vertical point load P H(t) (Pekeris
// 1955; general Poisson ratio in the integral form of Verruijt, An
// Introduction to Soil Dynamics, ch. 13.2), evaluated here by our own
// quadrature, and its convolution with a smooth load signature.
//
// Normalisation: tau = Vs t / r; w = wbar(tau) P / (G r), w positive in the
// direction of the load (downward for a downward load). wbar = 0 for tau <
// Vs/Vp (P arrival), singular at the Rayleigh arrival tau_R = Vs / c_R and
// tends to the static (Boussinesq) value (1 - nu) / (2 pi).
#pragma once

#include <vector>

#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

class PekerisSolution {
 public:
  explicit PekerisSolution(const Material& m);

  double tauP() const { return eta_; }
  double tauS() const { return 1.0; }
  double tauR() const { return tau_r_; }
  double staticValue() const;
  /// Normalised step response wbar(tau) (principal value after tau_R).
  double stepNormalised(double tau) const;
  /// w(r, t) for the step load P H(t).
  double stepDisplacement(double p_n, double r_m, double t_s) const;
  /// w(r, t) for the load P S(t), S a raised-cosine step rising over [0, rise_s]
  /// (S = (1 - cos(pi t / rise)) / 2), at the given times.
  std::vector<double> smoothStepResponse(double p_n, double r_m, double rise_s, const std::vector<double>& t_s) const;
  /// Same for the Hann pulse S = (1 - cos(2 pi t / T)) / 2 on [0, T], 0 elsewhere.
  std::vector<double> hannPulseResponse(double p_n, double r_m, double duration_s,
                                        const std::vector<double>& t_s) const;

 private:
  std::vector<double> response(double p_n, double r_m, double rise_s, const std::vector<double>& t_s, bool pulse) const;
  double denominator(double s) const;       // rationalised Rayleigh function D(y^2)
  double denominatorSlope(double s) const;  // dD / ds
  Material mat_;
  double eta_ = 0.0, tau_r_ = 0.0, vs_ = 0.0, g_ = 0.0;
};

/// FE Lamb benchmark: quarter box (symmetry planes x = 0, y = 0), Lysmer
/// dashpots elsewhere, point load at the corner surface node with a
/// raised-cosine step signature; surface vertical displacement along x.
struct LambSpec {
  Material material{2.5e7, 2000.0, 0.25};  // Vs = 70.7 m/s, Vp = 122 m/s
  double h_m = 0.25;
  double half_width_m = 14.0;
  double depth_m = 14.0;
  /// Load signature: Hann pulse of this duration (true) or raised-cosine step rising over it.
  bool pulse = true;
  double rise_s = 0.05;
  double load_n = 1.0e4;
  std::vector<double> distances_m = {4.0, 6.0, 8.0};
  /// Simulated time (0 = until the pulse has passed the farthest station).
  double duration_s = 0.0;
  /// Boundary on the absorbing faces (default: Lysmer dashpots; a graded layer or a PML lies inside the box).
  BoundarySpec boundary;
  Precision precision = Precision::Float;
  KernelKind kernel = KernelKind::Element;
};

struct LambStation {
  double r_m = 0.0;
  double t_p_fe_s = 0.0, t_p_an_s = 0.0;  // first time |w| exceeds 2 % of the peak (P arrival), interpolated
  double t_r_fe_s = 0.0, t_r_an_s = 0.0;  // time of the peak |w| (Rayleigh pulse), parabolic refinement
  double peak_fe_m = 0.0, peak_an_m = 0.0;
  double elements_per_rayleigh_wavelength = 0.0;  // at the dominant frequency 1 / rise
};

struct LambResult {
  std::vector<LambStation> stations;
  std::vector<double> t_s;
  std::vector<std::vector<double>> w_fe, w_an;  // per station
  double dt_s = 0.0;
  size_t elements = 0;
};

LambResult runLamb(const LambSpec& spec);

/// Boundary reflections: the Lamb pulse in a small box vs the same in a large
/// reference box (whose reflections arrive after the window). Figures at the
/// station r over the window: peak = max |w_small - w_ref| / max |w_ref|;
/// band = sqrt(sum |D(f)|^2 / sum |W_ref(f)|^2) over 1 Hz lines of a band (D, W_ref
/// the Fourier transforms of the difference and of the reference), i.e. the rms
/// reflected / direct amplitude ratio in that band. An absorbing zone (graded layer, PML)
/// is added outside the small box (same region of interest; the box grows by its thickness).
struct ReflectionCase {
  /// The box grows by this on its absorbing sides (and below when `bottom`); 0: the box itself.
  double layer_m = 0.0;
  bool bottom = true;
  /// Boundary of the enlarged box, its zone filling the added strip (dashpots: no zone).
  BoundarySpec boundary;

  /// A graded layer L thick (max_alpha 0: the box enlarged by L, dashpots only).
  static ReflectionCase gradedLayer(double thickness_m, double max_alpha_1_s, double exponent, bool bottom);
  /// A PML of spec.thickness_m (along the bottom when spec.bottom).
  static ReflectionCase pml(const PmlSpec& spec);
};
struct ReflectionRow {
  ReflectionCase absorber;
  double peak = 0.0;
  double band_10_50 = 0.0;                                      // 10-50 Hz
  double band_10_20 = 0.0, band_20_35 = 0.0, band_35_50 = 0.0;  // 10-20, 21-35, 36-50 Hz
  double band_21_30 = 0.0, band_31_40 = 0.0, band_41_50 = 0.0;  // and 21-30, 31-40, 41-50 Hz
  size_t elements = 0;
  double dt_s = 0.0;
};
struct ReflectionResult {
  double r_m = 0.0, window_s = 0.0;
  size_t reference_elements = 0;
  std::vector<ReflectionRow> rows;  // one per case, in order
};
ReflectionResult runBoundaryReflection(double small_half_width_m, const std::vector<ReflectionCase>& cases);

/// The same on a layered profile (e.g. Haren's, as meshed by buildMesh from f_max and
/// elements per wavelength): quarter model, vertical Hann pulse point load at the corner,
/// box of interest box_half_width_m x box_depth_m (an absorbing zone is added outside it
/// along the sides, and below it when ReflectionCase::bottom), compared with a reference box
/// (same element size and depth grading, the half-space levels continued) over window_s.
struct LayeredReflectionSpec {
  std::vector<Layer> profile;  // layers then the half-space
  double f_max_hz = 50.0, elements_per_wavelength = 8.0;
  double rayleigh_beta_s = 0.0, damping_cutoff_hz = 300.0;
  double box_half_width_m = 16.0, box_depth_m = 12.0;
  double reference_half_width_m = 48.0, reference_depth_m = 30.0;
  double pulse_s = 0.025;
  double window_s = 0.4;
  std::vector<double> distances_m = {8.0, 14.0};
  Precision precision = Precision::Float;
};
struct LayeredReflectionRow {
  ReflectionCase absorber;
  std::vector<ReflectionRow> stations;  // per distance
  size_t elements = 0;
};
struct LayeredReflectionResult {
  double h_m = 0.0, dt_s = 0.0;
  size_t reference_elements = 0;
  std::vector<LayeredReflectionRow> rows;
};
LayeredReflectionResult runLayeredReflection(const LayeredReflectionSpec& spec,
                                             const std::vector<ReflectionCase>& cases);

/// Reflection figures of a signal against a reference sampled at the same times (dt): see ReflectionResult.
ReflectionRow reflectionFigures(const std::vector<double>& w, const std::vector<double>& w_ref, double dt_s);

}  // namespace railvib::soil
