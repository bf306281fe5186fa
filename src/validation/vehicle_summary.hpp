// railvib/validation (private): the modes the paper's Table 1 and Fig. 9 name, picked out of a
// vehicle's mode list.
#pragma once

#include <string>
#include <vector>

#include "railvib/vehicle/modal.hpp"

namespace railvib::validation {

struct VehicleModeSummary {
  double carbody_bounce_hz = 0.0;  ///< lowest mode named car-body bounce
  /// Lowest leading-bogie mode (bounce or pitch by the kinematic rule) with the largest bogie share
  /// among its near neighbours (the flexible track splits it), and where it turns.
  double bogie_first_hz = 0.0;
  double bogie_first_pivot_m = 0.0;          ///< behind the bogie centre (negative: ahead)
  double bogie_first_pivot_to_axle_m = 0.0;  ///< distance of that pivot from the nearer axle of the bogie
  /// Lowest leading-bogie mode turning within half the half-wheelbase of the bogie centre.
  double bogie_pitch_hz = 0.0;
  /// Hop of the leading bogie's motor wheel (axle hop (motor wheels, leading bogie)).
  double motor_hop_hz = 0.0;
};

VehicleModeSummary summarise(const vehicle::VehicleModel& model, const std::vector<vehicle::Mode>& modes);

std::string fixed(double v, int digits);

}  // namespace railvib::validation
