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

/// Analytic direct receptance (m/N) of the continuous Euler-Bernoulli beam on a
/// smeared 2-layer support (pad / sleeper mass / ballast per metre, ballast on
/// a rigid base; Knothe & Grassie, Vehicle System Dynamics 22, 1993). Convention: load F e^{i w t},
/// positive downward.
std::complex<double> continuousBeamReceptance(const TrackParams& p, double frequency_hz);

/// Static deflection under a point load of the continuous beam on a smeared
/// Winkler support of stiffness per metre k (N/m^2): F / (8 EI b^3), b = (k / 4EI)^(1/4).
double winklerBeamStaticDeflection(double bending_stiffness_n_m2, double support_n_m2, double force_n);

/// Static support stiffness per metre of the track (series pad + ballast [+ Winkler spring]) / spacing.
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
/// stiffness replaces the rigid model's k_b* I. Reproduces the Winkler and CLM tracks exactly when
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
