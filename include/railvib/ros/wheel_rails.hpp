// railvib ROS layer: the rail under each wheel as ContactForces.wheel_rail carries it (one code per
// wheel; the codes are the track core's Rail values), in one place for the nodes that publish and
// check it.
#pragma once

#include <cstdint>
#include <vector>

#include "railvib/ContactForces.h"
#include "railvib/track/track_model.hpp"

namespace railvib::ros_io {

static_assert(railvib::ContactForces::LEFT == static_cast<uint8_t>(track::Rail::Left) &&
                  railvib::ContactForces::RIGHT == static_cast<uint8_t>(track::Rail::Right),
              "ContactForces.wheel_rail codes are the track core's Rail values");

inline std::vector<uint8_t> wheelRailCodes(const std::vector<track::Rail>& rails) {
  std::vector<uint8_t> codes;
  codes.reserve(rails.size());
  for (track::Rail r : rails) codes.push_back(static_cast<uint8_t>(r));
  return codes;
}

}  // namespace railvib::ros_io
