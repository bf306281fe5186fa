// railvib/signal: one-third-octave band velocity levels.
#include "railvib/signal/third_octave.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace railvib::signal {

double thirdOctaveNominal(int index) {
  static const double mantissa[10] = {1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0};
  const int decade = static_cast<int>(std::floor(static_cast<double>(index) / 10.0));
  const int m = index - 10 * decade;
  return mantissa[m] * std::pow(10.0, decade);
}

std::vector<ThirdOctaveBand> thirdOctaveBands(double f_min_nominal_hz, double f_max_nominal_hz, double fs_hz) {
  std::vector<ThirdOctaveBand> bands;
  const int lo = static_cast<int>(std::floor(10.0 * std::log10(f_min_nominal_hz) - 0.5));
  const int hi = static_cast<int>(std::ceil(10.0 * std::log10(f_max_nominal_hz) + 0.5));
  for (int n = lo; n <= hi; ++n) {
    ThirdOctaveBand b;
    b.index = n;
    b.nominal_hz = thirdOctaveNominal(n);
    b.centre_hz = std::pow(10.0, n / 10.0);
    b.lower_hz = b.centre_hz * std::pow(10.0, -0.05);
    b.upper_hz = b.centre_hz * std::pow(10.0, 0.05);
    if (b.nominal_hz < f_min_nominal_hz * (1 - 1e-9) || b.nominal_hz > f_max_nominal_hz * (1 + 1e-9)) continue;
    if (fs_hz > 0.0 && b.upper_hz >= 0.45 * fs_hz) continue;
    bands.push_back(b);
  }
  return bands;
}

ThirdOctaveAnalyzer::ThirdOctaveAnalyzer(double fs_hz, std::vector<ThirdOctaveBand> bands, double tau_s,
                                         double v_ref_m_s)
    : fs_(fs_hz), bands_(std::move(bands)), v_ref_(v_ref_m_s) {
  if (!(tau_s > 0.0) || !(v_ref_m_s > 0.0)) throw std::invalid_argument("ThirdOctaveAnalyzer: tau and v_ref > 0");
  for (const auto& b : bands_) {
    if (b.upper_hz >= 0.45 * fs_hz) {
      throw std::invalid_argument("ThirdOctaveAnalyzer: band " + std::to_string(b.nominal_hz) +
                                  " Hz too close to the Nyquist frequency of fs = " + std::to_string(fs_hz) + " Hz");
    }
    filters_.push_back(butterworthBandpass(3, b.lower_hz, b.upper_hz, fs_hz));
  }
  alpha_ = std::exp(-1.0 / (fs_hz * tau_s));
  running_.assign(bands_.size(), 0.0);
  sum_.assign(bands_.size(), 0.0);
  max_running_.assign(bands_.size(), 0.0);
}

void ThirdOctaveAnalyzer::process(double v) {
  for (size_t i = 0; i < filters_.size(); ++i) {
    const double y = filters_[i].process(v);
    const double sq = y * y;
    running_[i] = alpha_ * running_[i] + (1.0 - alpha_) * sq;
    sum_[i] += sq;
    max_running_[i] = std::max(max_running_[i], running_[i]);
  }
  ++count_;
}

double ThirdOctaveAnalyzer::toDb(double mean_square) const {
  if (!(mean_square > 0.0)) return -std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(mean_square / (v_ref_ * v_ref_));
}

std::vector<double> ThirdOctaveAnalyzer::runningLevelsDb() const {
  std::vector<double> l(running_.size());
  for (size_t i = 0; i < l.size(); ++i) l[i] = toDb(running_[i]);
  return l;
}

std::vector<double> ThirdOctaveAnalyzer::maxRunningLevelsDb() const {
  std::vector<double> l(max_running_.size());
  for (size_t i = 0; i < l.size(); ++i) l[i] = toDb(max_running_[i]);
  return l;
}

std::vector<double> ThirdOctaveAnalyzer::equivalentLevelsDb() const {
  std::vector<double> l(sum_.size());
  for (size_t i = 0; i < l.size(); ++i) l[i] = toDb(count_ ? sum_[i] / static_cast<double>(count_) : 0.0);
  return l;
}

void ThirdOctaveAnalyzer::resetEquivalent() {
  sum_.assign(sum_.size(), 0.0);
  count_ = 0;
}

std::vector<double> thirdOctaveLevels(const std::vector<double>& velocity_m_s, double fs_hz,
                                      const std::vector<ThirdOctaveBand>& bands, double v_ref_m_s, double settle_s) {
  ThirdOctaveAnalyzer a(fs_hz, bands, 1.0, v_ref_m_s);
  const size_t skip = std::min(velocity_m_s.size(), static_cast<size_t>(std::llround(settle_s * fs_hz)));
  a.process(velocity_m_s.data(), skip);
  a.resetEquivalent();
  a.process(velocity_m_s.data() + skip, velocity_m_s.size() - skip);
  return a.equivalentLevelsDb();
}

}  // namespace railvib::signal
