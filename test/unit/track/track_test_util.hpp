// Shared helpers of the track unit tests.
#pragma once

#include <string>

#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"

#ifndef RAILVIB_SOURCE_DIR
#define RAILVIB_SOURCE_DIR "."
#endif

namespace railvib::track::test {

inline std::string configPath(const std::string& name) { return std::string(RAILVIB_SOURCE_DIR) + "/config/" + name; }

/// The Haren track parameters as configured (config/track_haren.yaml), with overrides.
inline TrackParams haren(const std::vector<std::string>& overrides = {}) {
  return loadTrackParams(Config::load(configPath("track_haren.yaml"), overrides).root());
}

}  // namespace railvib::track::test
