// Shared helpers of the vehicle unit tests.
#pragma once

#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"

namespace railvib::vehicle::test {

/// The whole Haren scenario (config/haren.yaml) with overrides.
inline Config haren(const std::vector<std::string>& overrides = {}) {
  return Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml", overrides);
}

/// Two override lists, a's then b's (b's win).
inline std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// A value with 3 significant digits, for messages.
inline std::string sci(double v) {
  std::ostringstream s;
  s << std::setprecision(3) << v;
  return s.str();
}

}  // namespace railvib::vehicle::test
