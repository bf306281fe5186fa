// Shared helpers of the track unit tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"

#ifndef RAILVIB_SOURCE_DIR
#define RAILVIB_SOURCE_DIR "."
#endif

namespace railvib::track::test {

/// n frequencies from f0 to f1 (Hz), evenly spaced on a log scale.
inline std::vector<double> logGrid(double f0, double f1, int n) {
  std::vector<double> f(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) f[static_cast<size_t>(i)] = f0 * std::pow(f1 / f0, static_cast<double>(i) / (n - 1));
  return f;
}

/// The largest |a - b| / |b| over two receptance curves of equal length.
inline double worstRelative(const std::vector<std::complex<double>>& a, const std::vector<std::complex<double>>& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]) / std::abs(b[i]));
  return worst;
}

inline std::string configPath(const std::string& name) { return std::string(RAILVIB_SOURCE_DIR) + "/config/" + name; }

/// The track file alone has no run to size an automatic extent from: the track tests give it the fixed
/// 100 m track (their own overrides come after these and win).
inline std::vector<std::string> fixedExtent(const std::vector<std::string>& overrides = {}) {
  std::vector<std::string> all{"track.extent.mode=fixed", "track.extent.x_min_m=-50", "track.extent.x_max_m=50"};
  all.insert(all.end(), overrides.begin(), overrides.end());
  return all;
}

/// The Haren track parameters as configured (config/track_haren.yaml) on the fixed 100 m track, with overrides.
inline TrackParams haren(const std::vector<std::string>& overrides = {}) {
  return loadTrackParams(Config::load(configPath("track_haren.yaml"), fixedExtent(overrides)).root());
}

/// The track of the whole Haren scenario (config/haren.yaml: with the site, so track.width=full has its
/// gauge) on the fixed 100 m track, with overrides.
inline TrackParams harenScenario(const std::vector<std::string>& overrides = {}) {
  return loadTrackParams(Config::load(configPath("haren.yaml"), fixedExtent(overrides)).root());
}

}  // namespace railvib::track::test
