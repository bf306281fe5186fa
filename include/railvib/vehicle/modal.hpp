// railvib/vehicle: modal analysis and wheel impedances of the vehicle
// linearised about its static equilibrium.
//
// Rigid track: each wheel sits on its linearised Hertz spring
// k_H = 1.5 C_H delta0^0.5 to ground; the damped eigenproblem is solved
// exactly (state space, 2 x the reduced DOF count).
// Flexible track: the vehicle (wheels at their static positions, x_front = 0
// by default) is coupled through the linearised Hertz springs to a local
// track model (same parameters, rail `margin_m` beyond the end axles, free
// rail ends, no absorbing layer). Undamped modes of the coupled system up to
// `basis_cutoff_hz` form a reduced basis on which the damped eigenproblem is
// solved (complex). Track modes are filtered out: a mode is kept when the
// vehicle holds more than `min_vehicle_energy_share` of its kinetic energy.
// Mode names come from the kinetic-energy distribution over the vehicle's
// bodies (car-body bounce/pitch/roll, <bogie> bounce/pitch/roll, axle hop,
// wheelset roll, tread). Full width: a mode is its own mirror image (the half
// vehicle's bounce and pitch) or its negative (roll, the sides in anti-phase);
// an anti-phase mode not named after a roll is named "..., anti-phase".
// The flexible track then has the vehicle's width: each wheel on its own rail.
#pragma once

#include <complex>
#include <limits>
#include <string>
#include <vector>

#include "railvib/vehicle/vehicle_model.hpp"

namespace railvib::track {
struct TrackParams;
}

namespace railvib::vehicle {

struct Mode {
  std::string name;                   ///< e.g. "car-body bounce", "leading bogie pitch"
  std::string body;                   ///< body with the largest kinetic energy share
  double frequency_hz = 0.0;          ///< undamped natural frequency |lambda| / 2 pi
  double damping_ratio = 0.0;         ///< -Re(lambda) / |lambda|
  double name_share = 0.0;            ///< vehicle kinetic energy share of the named category (bogies: bounce + pitch)
  double vehicle_energy_share = 1.0;  ///< share of the total kinetic energy in the vehicle (flexible)
  /// Bogie modes: where the bogie's vertical motion vanishes, behind its centre (m; negative =
  /// ahead, towards the front axle; NaN when it does not pitch). Within half the wheelbase the mode
  /// is named pitch, else bounce: a bogie turning about one axle is a pitch, even when most of its
  /// kinetic energy is in the vertical motion of its centre.
  double pivot_offset_m = std::numeric_limits<double>::quiet_NaN();
  /// Full width: share of the vehicle's kinetic energy in the motion antisymmetric about the centre
  /// line (0: bounce/pitch, the half vehicle's; 1: roll and the sides in anti-phase); 0 at half width.
  double antisymmetric_share = 0.0;
};

/// The loads of a wheel impedance at full width: the wheel alone, or with the other wheel of its
/// axle loaded alike (in phase: the half vehicle's case) or opposite (anti-phase). The half vehicle
/// is the in-phase case already: it takes OneWheel or InPhase (the same), not AntiPhase.
enum class AxleLoading { OneWheel, InPhase, AntiPhase };

struct ModalOptions {
  double margin_m = 6.0;
  double basis_cutoff_hz = 600.0;
  double min_vehicle_energy_share = 0.3;
  double front_axle_x_m = 0.0;
};

/// Linearised Hertz stiffness per wheel at the static equilibrium on a rigid track (N/m).
std::vector<double> linearisedHertzStiffness(const VehicleModel& model);

std::vector<Mode> vehicleModesRigid(const VehicleModel& model);
std::vector<Mode> vehicleModesFlexible(const VehicleModel& model, const track::TrackParams& track,
                                       const ModalOptions& options = {});

/// Direct impedance F/v (N s/m) at wheel `wheel` (an index of model.wheels(); force and velocity
/// on the contact DOF: tread of a motor wheel) on a rigid track, and on the flexible track (full
/// track model with its ends, cross-receptances between wheels; of the vehicle's width). Full
/// width: `loading` says whether the other wheel of the axle carries F too (in phase) or -F.
std::vector<std::complex<double>> wheelImpedanceRigid(const VehicleModel& model, int wheel,
                                                      const std::vector<double>& frequencies_hz,
                                                      AxleLoading loading = AxleLoading::OneWheel);
std::vector<std::complex<double>> wheelImpedanceFlexible(const VehicleModel& model, const track::TrackParams& track,
                                                         int wheel, const std::vector<double>& frequencies_hz,
                                                         double front_axle_x_m = 0.0,
                                                         AxleLoading loading = AxleLoading::OneWheel);

}  // namespace railvib::vehicle
