#include "railvib/ros/tram_display.hpp"

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

}  // namespace railvib::ros_io
