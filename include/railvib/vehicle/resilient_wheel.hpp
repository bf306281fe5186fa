// railvib/vehicle: the closed form of a resilient wheel seen from its contact (issue 33, resilient
// wheels as a source-side mitigation measure; docs/vehicle.md, "Resilient wheels").
//
// A resilient wheel is a chain of lumped bodies: the tread m_t (the contact body) on the resilient
// ring (k_t, d_t) under the hub m_h, the hub on the element (k_p, d_p, the primary suspension) that
// holds it from above, and the body above. On a rigid track the tread stands on the linearised Hertz
// spring k_H. With s = k + i w d the dynamic stiffness of a spring-damper and the body above taken
// either as blocked or as a free point mass M_u, the direct dynamic stiffness at the tread is the
// series/parallel composition of the chain (any structural-dynamics textbook's driving-point
// dynamic stiffness of a chain of masses and springs: Inman, Engineering Vibration, on systems
// of several degrees of freedom):
//   D_u = -w^2 M_u (free mass), or infinite (blocked)
//   D_h = -w^2 m_h + s_p D_u / (s_p + D_u)          (-> -w^2 m_h + s_p when blocked)
//   D_t = k_H - w^2 m_t + s_t D_h / (s_t + D_h)
// and the impedance F / v at the tread Z = D_t / (i w). Its undamped natural frequencies are the
// roots of det(K - w^2 M) of the 2 (blocked) or 3 (free mass) bodies: a quadratic or a cubic in w^2
// (three real roots: the trigonometric form of Cardano's solution); the highest is the tread on its
// ring and the contact, the ring's resonance.
#pragma once

#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "railvib/vehicle/vehicle_model.hpp"

namespace railvib::vehicle {

/// A resilient wheel of the half vehicle, per rail, from the model's bodies and elements.
struct ResilientWheelChain {
  std::string tread, hub, upper;  ///< body names: the contact body, the hub, the body above
  double tread_mass_kg = 0.0;
  double hub_mass_kg = 0.0;
  double upper_mass_kg = 0.0;  ///< the body above (its mass on the rail), for ChainTop::FreeMass
  double ring_stiffness_n_m = 0.0;
  double ring_damping_n_s_m = 0.0;
  double primary_stiffness_n_m = 0.0;  ///< the element holding the hub
  double primary_damping_n_s_m = 0.0;
  double hertz_stiffness_n_m = 0.0;  ///< linearised at the static wheel load (rigid track)
};

/// How the closed form ends above the hub's element.
enum class ChainTop {
  Blocked,   ///< the body above does not move (exact above its own modes, for a heavy bogie)
  FreeMass,  ///< the body above is a free point mass on nothing else (exact for such a rig)
};

/// The chain of `wheel` (an index of model.wheels()): nullopt unless the half vehicle's contact body
/// is a tread held by one element (its ring) under a point body (the hub) held by one element.
std::optional<ResilientWheelChain> resilientWheelChain(const VehicleModel& model, int wheel);

/// Closed form of the direct impedance F / v at the tread (N s/m) at f_hz.
std::complex<double> resilientWheelImpedance(const ResilientWheelChain& chain, double f_hz, ChainTop top);

/// Closed-form undamped natural frequencies (Hz), ascending: 2 (blocked) or 3 (free mass); the last is
/// the ring's resonance.
std::vector<double> resilientWheelFrequencies(const ResilientWheelChain& chain, ChainTop top);

}  // namespace railvib::vehicle
