// railvib/soil: the soil's vertical dynamic compliance between sleeper footprints, from one impulse
// run of the FE soil (the "rigorous" track-soil model the CLM foundation approximates: paper,
// section 2.2 and Fig. 4).
//
// A vertical Hann force pulse on the footprint of the sleeper nearest the centre of the loadable
// region (footprint.hpp); the load-weighted mean displacement of that footprint and of the footprints
// k = 1..K sleepers away on both sides is recorded at every step. In the frequency domain
//   H_k(f) = U_k(f) / F(f),   U, F the Fourier integrals sum_n x(t_n) e^{-i 2 pi f t_n} dt,
// evaluated directly at any f (no FFT grid): the displacement of a footprint k sleepers away per
// unit force on the loaded one, averaged over the two sides (a layered soil is invariant along the
// track: H depends on the distance only; the two sides differ by how the footprints fall on the
// element grid, reported as `side_difference`). Valid up to the mesh's f_max (soil.mesh.f_max_hz)
// and where the pulse has energy (its spectrum falls to zero at 2 / pulse_s); the run must be long
// enough for the response to die out (reported as `tail_share`).
#pragma once

#include <complex>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "railvib/soil/soil_params.hpp"

namespace railvib::soil {

struct FootprintComplianceSpec {
  /// Peak of the Hann force pulse (N) and its duration (s).
  double force_n = 1.0e4;
  double pulse_s = 0.02;
  /// Simulated time (s).
  double duration_s = 1.5;
  /// The furthest footprint read (m from the loaded one); 0 = as far as the loadable region allows
  /// on both sides.
  double max_distance_m = 0.0;
};

class FootprintCompliance {
 public:
  /// Runs the FE soil of `params` (mesh, layers, boundary, damping, threads; one rank) with the
  /// pulse on one footprint of the track layout params.track. Throws std::invalid_argument for a
  /// spec that is not finite and positive, a box with fewer than 2 footprints on each side of the
  /// loaded one, or a pulse shorter than 4 steps.
  FootprintCompliance(const SoilParams& params, const FootprintComplianceSpec& spec);

  /// Sleeper spacing (m): footprint k lies k spacings from the loaded one.
  double spacingM() const { return spacing_m_; }
  /// K + 1: the loaded footprint (k = 0) and K on each side.
  size_t distanceCount() const { return displacement_m_.size(); }
  /// H_k(f) (m/N): downward displacement of the footprint k sleepers away per unit downward force on
  /// the loaded footprint (mean of the two sides). Throws std::out_of_range for k >= distanceCount().
  std::complex<double> compliance(size_t k, double frequency_hz) const;
  /// Highest frequency the result stands for: the mesh's f_max.
  double maxFrequencyHz() const { return f_max_hz_; }
  /// x of the loaded footprint (m), the step (s), steps taken, wall time (s).
  double loadedX() const { return loaded_x_m_; }
  double dt() const { return dt_s_; }
  uint64_t steps() const { return steps_; }
  /// Run figures: mesh, step, distances, tail_share (rms of the loaded footprint's displacement over
  /// the last 10 % of the run / its rms over the run), side_difference (largest rms difference of
  /// the two sides' histories / rms of their mean, over k >= 1), seconds.
  nlohmann::json summary() const;

 private:
  double spacing_m_ = 0.0, loaded_x_m_ = 0.0, dt_s_ = 0.0, f_max_hz_ = 0.0, seconds_ = 0.0;
  double tail_share_ = 0.0, side_difference_ = 0.0;
  uint64_t steps_ = 0;
  size_t elements_ = 0;
  std::vector<double> force_n_;                      // F(t_n)
  std::vector<std::vector<double>> displacement_m_;  // [k][n], mean of the two sides
};

}  // namespace railvib::soil
