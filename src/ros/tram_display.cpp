#include "railvib/ros/tram_display.hpp"

#include <stdexcept>

namespace railvib::ros_io {

double tramDisplayHeight(vehicle::BodyKind kind, double wheel_radius_m) {
  switch (kind) {
    case vehicle::BodyKind::Carbody:
      // Box centre: low floor at 0.35 m, roof at 3.3 m above the rail head.
      return kRailHeadDisplayZM + 0.35 + 0.5 * kTramCarbodyHeightM;
    case vehicle::BodyKind::Bogie:
      return kRailHeadDisplayZM + wheel_radius_m;
    default:
      return kRailHeadDisplayZM + wheel_radius_m;  // wheel centres
  }
}

std::vector<CarbodySection> carbodySections(const vehicle::VehicleParams& params) {
  const auto& centre = params.carbody_com_offsets_m;
  const auto& joint = params.articulation_offsets_m;
  if (centre.size() != 3 || joint.size() != 2) {
    throw std::invalid_argument("carbodySections: expected 3 carbodies and 2 articulations");
  }
  return {{2.0 * centre[0] - joint[0], joint[0]}, {joint[0], joint[1]}, {joint[1], 2.0 * centre[2] - joint[1]}};
}

}  // namespace railvib::ros_io
