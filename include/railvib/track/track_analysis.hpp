// railvib/track: frequency-domain helpers (receptance curves, peaks, analytic references).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <vector>

#include "railvib/track/track_model.hpp"

namespace railvib::track {

/// A resonance peak of |receptance| (parabolic interpolation in log|.| on the grid).
struct ReceptancePeak {
  double frequency_hz = 0.0;
  double magnitude_m_n = 0.0;
};

/// Local maxima of |r(f)| on a uniform or non-uniform grid, sorted by frequency.
std::vector<ReceptancePeak> findPeaks(const std::vector<double>& f_hz, const std::vector<std::complex<double>>& r);

/// Pinned-pinned frequency of the rail between sleepers (Hz).
double pinnedPinnedFrequency(const TrackParams& p);

/// The support of the continuous beam smeared per metre of track (complex stiffnesses s* = (k + i w d)
/// / L, L the sleeper spacing): railpad s_p over the sleeper mass m_s over the layers below the
/// sleeper in series through massless junctions (under-sleeper pad, ballast, under-ballast mat and,
/// on the Winkler foundation, its spring and damper; rigid: a fixed base). The CLM (masses coupled
/// along the track) has no such closed form: std::invalid_argument.
struct SmearedSupport {
  /// s_below: the series layers under the sleeper (N/m^2).
  std::complex<double> below_sleeper_n_m2;
  /// s_tot = s_p (s_below - m_s w^2) / (s_p + s_below - m_s w^2): support force per metre per rail
  /// deflection (N/m^2).
  std::complex<double> rail_support_n_m2;
  /// H = s_p s_below / (s_p + s_below - m_s w^2): force into the ground per metre per rail deflection
  /// (N/m^2; every layer below the sleeper carries it, the junctions being massless).
  std::complex<double> ground_force_n_m2;
};
SmearedSupport smearedSupport(const TrackParams& p, double frequency_hz);

/// Analytic direct receptance (m/N) of the continuous Euler-Bernoulli beam on the smeared layered
/// support (smearedSupport: pad / sleeper mass / ballast per metre, with any resilient layers, on a
/// rigid base or the Winkler foundation; Knothe & Grassie, Vehicle System Dynamics 22, 1993):
/// k^4 = (m_r w^2 - s_tot) / EI, alpha(0) = -(1 + i) / (4 EI k^3). Convention: load F e^{i w t},
/// positive downward. Throws std::invalid_argument for the CLM foundation.
std::complex<double> continuousBeamReceptance(const TrackParams& p, double frequency_hz);

/// Analytic force transmissibility of the same continuous beam: the total force into the ground
/// (integrated along the track) per unit harmonic rail load, T = H / (s_tot - m_r w^2) (the beam
/// equation EI w'''' - m_r w^2 w + s_tot w = F delta(x) integrated over x gives int w dx =
/// F / (s_tot - m_r w^2); the ground takes H w per metre). T(0) = 1 (statics). Throws
/// std::invalid_argument for the CLM foundation.
std::complex<double> continuousBeamForceTransmissibility(const TrackParams& p, double frequency_hz);

/// Discrete track: the total force on the foundation (sum over every sleeper and rail seat of
/// TrackModel::ballastForceOnFoundation: the ballast's, or the under-ballast mat's) per N of harmonic
/// rail load at x (Left / Right: 1 N on that rail; Both: 1 N on each rail, the sum divided by 2).
std::vector<std::complex<double>> foundationForceTransmissibility(const TrackModel& model, double x_m,
                                                                  const std::vector<double>& frequencies_hz,
                                                                  RailLoading loading = RailLoading::Left);

/// Insertion loss (dB) of a measure on a transfer function: 20 log10(|without| / |with|), positive
/// where the measure reduces the transfer.
double insertionLossDb(std::complex<double> without, std::complex<double> with);

/// The frequencies (Hz) where a curve sampled on a grid crosses zero (linear interpolation between
/// grid points of opposite sign), in increasing order.
std::vector<double> zeroCrossings(const std::vector<double>& f_hz, const std::vector<double>& values);

/// Static deflection under a point load of the continuous beam on a smeared
/// Winkler support of stiffness per metre k (N/m^2): F / (8 EI b^3), b = (k / 4EI)^(1/4).
double winklerBeamStaticDeflection(double bending_stiffness_n_m2, double support_n_m2, double force_n);

/// Static support stiffness per metre of the track (series pad + [under-sleeper pad +] ballast
/// [+ under-ballast mat] [+ Winkler spring]) / spacing.
double smearedStaticSupportStiffness(const TrackParams& p);

/// A ground under the ballast given in the frequency domain (a soil model's): its vertical dynamic
/// compliance between the sleepers' footprints at one frequency (m/N, complex, sleepers x sleepers):
/// entry (i, j) is the downward displacement of the ground under sleeper i per unit downward ballast
/// force of the modelled track (the half track's rail seat) at sleeper j.
using GroundCompliance = std::function<Eigen::MatrixXcd(double frequency_hz)>;

/// Direct receptance (m/N) of the rail at x with the ballast standing on `ground` instead of a
/// foundation model. The model must have the rigid foundation (ballast to a fixed base) and one rail
/// (track.width: half): the ballast springs then become springs to ground points whose motion is
/// the ground's, u_g = G f_b, so that the ballast forces are f_b = k_b* (I + k_b* G)^-1 u_s
/// (k_b* = k_b + i w d_b, u_s the sleepers' displacements), and that dense sleeper-to-sleeper
/// stiffness replaces the rigid model's k_b* I. With an under-ballast mat the mat stands on the
/// ground (k_b* its stiffness, u_s the mat nodes'); with an under-sleeper pad alone the ballast's top
/// is the pad node. Reproduces the Winkler and CLM tracks exactly when
/// G is their foundation's compliance (test_track). Throws std::invalid_argument.
std::vector<std::complex<double>> receptanceOnGround(const TrackModel& model, double x_m,
                                                     const std::vector<double>& frequencies_hz,
                                                     const GroundCompliance& ground);

/// Constant loads moving over the track from static equilibrium: calls sink(t, half-track ballast
/// forces per sleeper) after every step (and once at t0 with the initial state).
/// Throws std::out_of_range if a load leaves the rail during the run.
struct MovingLoadRun {
  double dt_s = 1e-4;
  double duration_s = 1.0;
  double front_start_m = 0.0;
  double speed_m_s = 0.0;
  std::vector<double> offsets_behind_m;
  std::vector<double> forces_n;
};
void simulateMovingLoads(const TrackModel& model, const MovingLoadRun& run,
                         const std::function<void(double t_s, const std::vector<double>& ballast_half_track_n)>& sink);

}  // namespace railvib::track
