// railvib/signal: one-third-octave band velocity levels.
//
// Bands: base-10 exact centres f_m = 10^(n/10) Hz (n integer, IEC 61260-1),
// edges f_m 10^(+-1/20), labelled with the nominal frequencies 1, 1.25, 1.6,
// 2, 2.5, 3.15, 4, 5, 6.3, 8 x 10^k. Each band is a 6th-order Butterworth band
// pass (3rd-order prototype, both edges pre-warped for the bilinear
// transform, gain 1 at the band centre), run as three second-order sections:
// streaming and the same filters for live and offline levels (class-1-like
// shape, no multirate; bands must lie below 0.45 fs).
// Levels L_v = 10 log10(mean(v^2) / v_ref^2) dB, v_ref = 1e-9 m/s (ISO 1683)
// or 5e-8 m/s; input velocity in m/s.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "railvib/signal/filter_design.hpp"

namespace railvib::signal {

constexpr double kVelocityRefIso1683 = 1e-9;  ///< m/s
constexpr double kVelocityRef5e8 = 5e-8;      ///< m/s (some railway practice)

struct ThirdOctaveBand {
  int index = 0;            ///< n: centre 10^(n/10) Hz
  double nominal_hz = 0.0;  ///< label (e.g. 31.5)
  double centre_hz = 0.0;   ///< exact 10^(n/10)
  double lower_hz = 0.0;
  double upper_hz = 0.0;
};

/// Nominal label of band n (e.g. 15 -> 31.5).
double thirdOctaveNominal(int index);
/// Bands with nominal centres in [f_min, f_max]; bands whose upper edge is
/// >= 0.45 fs_hz are left out (pass fs_hz = 0 for no limit).
std::vector<ThirdOctaveBand> thirdOctaveBands(double f_min_nominal_hz, double f_max_nominal_hz, double fs_hz = 0.0);

/// Streaming filter bank: running (exponential, time constant tau) and
/// equivalent (linear mean since start / resetEquivalent) band levels.
class ThirdOctaveAnalyzer {
 public:
  ThirdOctaveAnalyzer(double fs_hz, std::vector<ThirdOctaveBand> bands, double tau_s = 1.0,
                      double v_ref_m_s = kVelocityRefIso1683);

  void process(double velocity_m_s);
  void process(const double* velocity_m_s, size_t n) {
    for (size_t i = 0; i < n; ++i) process(velocity_m_s[i]);
  }
  const std::vector<ThirdOctaveBand>& bands() const { return bands_; }
  /// Running levels (dB), exponential averaging with tau.
  std::vector<double> runningLevelsDb() const;
  /// Equivalent levels over every sample since start or resetEquivalent() (dB).
  std::vector<double> equivalentLevelsDb() const;
  /// Max of the running level per band since start (dB).
  std::vector<double> maxRunningLevelsDb() const;
  void resetEquivalent();
  /// Response of band i's filter at f.
  double bandResponse(size_t i, double f_hz) const { return std::abs(filters_[i].response(f_hz, fs_)); }

 private:
  double toDb(double mean_square) const;
  double fs_;
  std::vector<ThirdOctaveBand> bands_;
  double v_ref_;
  double alpha_;
  std::vector<BiquadCascade> filters_;
  std::vector<double> running_, sum_, max_running_;
  uint64_t count_ = 0;
};

/// Offline equivalent levels of a whole record (m/s), same filter bank; the
/// first `settle_s` seconds (filter start-up) are excluded from the mean.
std::vector<double> thirdOctaveLevels(const std::vector<double>& velocity_m_s, double fs_hz,
                                      const std::vector<ThirdOctaveBand>& bands, double v_ref_m_s = kVelocityRefIso1683,
                                      double settle_s = 0.0);

}  // namespace railvib::signal
