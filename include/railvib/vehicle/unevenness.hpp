// railvib/vehicle: rail unevenness seen by a wheel (height, m, positive UP).
//
// Sum of (a) the local defect (a rectangular pad of height h and length l
// starting at x_p) seen through the wheel curvature: the wheel centre cannot
// follow the pad edges, the contact height is the envelope
//     z(x) = max_xi [ r(xi) + sqrt(R^2 - (x - xi)^2) ] - R,
// which for a flat-topped pad has the closed form
//     z(x) = max(0, h - R + sqrt(R^2 - d^2)),  d = distance from x to [x_p, x_p + l],
// i.e. the wheel starts climbing sqrt(2Rh - h^2) before the pad (per wheel
// radius); (b) an optional random irregularity drawn from a one-sided PSD
// (sum of cosines with seeded random phases, precomputed on a grid); (c) an
// optional measured profile read from a CSV (x_m, z_m), linearly interpolated,
// zero outside its range. (b) and (c) are taken as seen by the wheel (their
// wavelengths are long compared with the contact patch).
//
// Per rail (full width, docs/vehicle.md "Unevenness per rail"): the defect on
// the left rail, the right or both (defect.rails); the random profile of the
// left rail is the half track's, the right rail's has the same PSD and the
// coherence gamma(W) = coherence exp(-decay W) with it, each component split
// into a part in phase with the left rail's and an independent one:
//     z_R = sum_k A_k [gamma_k cos(W_k x + phi_k) + sqrt(1 - gamma_k^2) cos(W_k x + psi_k)];
// a measured profile is one column for both rails (z_m) or one per rail
// (z_left_m, z_right_m). The half track has the left rail only, its
// symmetric special case: both rails alike.
#pragma once

#include <vector>

#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::vehicle {

/// Closed-form envelope of a rectangular pad seen by a wheel of radius R.
double defectEnvelope(double x_m, const DefectParams& defect, double wheel_radius_m);
/// Brute-force envelope max_xi [r(xi) + sqrt(R^2 - (x - xi)^2)] - R over a fine grid (tests).
double defectEnvelopeBruteForce(double x_m, const DefectParams& defect, double wheel_radius_m, int samples = 20001);
/// Distance before the pad where the wheel starts climbing: sqrt(2Rh - h^2).
double defectClimbLength(const DefectParams& defect, double wheel_radius_m);

class Unevenness {
 public:
  /// Random profile generated over [x_min, x_max] (m). Throws ConfigError-free
  /// std::runtime_error if the measured CSV cannot be read or is not increasing.
  Unevenness(const UnevennessParams& params, double x_min_m, double x_max_m);

  /// Height seen by a wheel of radius R at x on a rail (m, positive up; the half track: Left).
  /// Throws std::invalid_argument for the right rail of the half track.
  double height(double x_m, double wheel_radius_m, track::Rail rail = track::Rail::Left) const;
  double defectHeight(double x_m, double wheel_radius_m, track::Rail rail = track::Rail::Left) const;
  double randomHeight(double x_m, track::Rail rail = track::Rail::Left) const;
  double measuredHeight(double x_m, track::Rail rail = track::Rail::Left) const;
  const UnevennessParams& params() const { return params_; }
  /// One-sided PSD of the random irregularity, m^2/(rad/m), at wavenumber W (rad/m).
  double psd(double wavenumber_rad_m) const;

 private:
  void checkRail(track::Rail rail) const;

  UnevennessParams params_;
  double grid_x0_ = 0.0, grid_dx_ = 1.0;
  std::vector<double> random_grid_[2];  // per rail (left, right); the half track: left only
  std::vector<double> measured_x_, measured_z_[2];
};

}  // namespace railvib::vehicle
