// railvib/signal: spectra of records (FFTW3).
#include "railvib/signal/spectrum.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "railvib/common/constants.hpp"

namespace railvib::signal {

namespace {

std::mutex& plannerMutex() {
  static std::mutex m;
  return m;
}
}  // namespace

std::vector<double> windowSamples(Window window, size_t n) {
  std::vector<double> w(n, 1.0);
  const double dn = static_cast<double>(n);
  for (size_t i = 0; i < n; ++i) {
    const double x = 2.0 * kPi * static_cast<double>(i) / dn;
    switch (window) {
      case Window::Rectangular:
        break;
      case Window::Hann:
        w[i] = 0.5 - 0.5 * std::cos(x);
        break;
      case Window::FlatTop:  // ISO 18431-2 / HFT-style 5-term flat top
        w[i] = 0.21557895 - 0.41663158 * std::cos(x) + 0.277263158 * std::cos(2 * x) - 0.083578947 * std::cos(3 * x) +
               0.006947368 * std::cos(4 * x);
        break;
    }
  }
  return w;
}

std::vector<std::complex<double>> realFft(const std::vector<double>& x) {
  const size_t n = x.size();
  if (n == 0) return {};
  std::vector<double> in(x);
  std::vector<std::complex<double>> out(n / 2 + 1);
  fftw_plan plan;
  {
    std::lock_guard<std::mutex> lock(plannerMutex());
    plan = fftw_plan_dft_r2c_1d(static_cast<int>(n), in.data(), reinterpret_cast<fftw_complex*>(out.data()),
                                FFTW_ESTIMATE);
  }
  fftw_execute(plan);
  {
    std::lock_guard<std::mutex> lock(plannerMutex());
    fftw_destroy_plan(plan);
  }
  return out;
}

std::vector<double> inverseRealFft(const std::vector<std::complex<double>>& spectrum, size_t n) {
  if (spectrum.size() != n / 2 + 1) throw std::invalid_argument("inverseRealFft: spectrum size must be n/2 + 1");
  std::vector<std::complex<double>> in(spectrum);
  std::vector<double> out(n);
  fftw_plan plan;
  {
    std::lock_guard<std::mutex> lock(plannerMutex());
    plan = fftw_plan_dft_c2r_1d(static_cast<int>(n), reinterpret_cast<fftw_complex*>(in.data()), out.data(),
                                FFTW_ESTIMATE);
  }
  fftw_execute(plan);
  {
    std::lock_guard<std::mutex> lock(plannerMutex());
    fftw_destroy_plan(plan);
  }
  for (double& v : out) v /= static_cast<double>(n);
  return out;
}

Spectrum amplitudeSpectrum(const std::vector<double>& x, double fs_hz, Window window) {
  const size_t n = x.size();
  if (n < 2) throw std::invalid_argument("amplitudeSpectrum: need at least 2 samples");
  const auto w = windowSamples(window, n);
  double gain = 0.0;
  std::vector<double> xw(n);
  for (size_t i = 0; i < n; ++i) {
    xw[i] = x[i] * w[i];
    gain += w[i];
  }
  const auto spec = realFft(xw);
  Spectrum s;
  s.frequency_hz.resize(spec.size());
  s.value.resize(spec.size());
  for (size_t k = 0; k < spec.size(); ++k) {
    s.frequency_hz[k] = static_cast<double>(k) * fs_hz / static_cast<double>(n);
    const bool edge = k == 0 || (n % 2 == 0 && k == n / 2);
    s.value[k] = (edge ? 1.0 : 2.0) * std::abs(spec[k]) / gain;
  }
  return s;
}

Spectrum powerSpectralDensity(const std::vector<double>& x, double fs_hz, size_t segment_length, Window window) {
  const size_t n = x.size();
  if (n < 2) throw std::invalid_argument("powerSpectralDensity: need at least 2 samples");
  const size_t m = std::clamp<size_t>(segment_length, 2, n);
  const size_t hop = std::max<size_t>(1, m / 2);
  const auto w = windowSamples(window, m);
  double wpow = 0.0;
  for (double v : w) wpow += v * v;
  Spectrum s;
  s.frequency_hz.resize(m / 2 + 1);
  s.value.assign(m / 2 + 1, 0.0);
  for (size_t k = 0; k < s.frequency_hz.size(); ++k) {
    s.frequency_hz[k] = static_cast<double>(k) * fs_hz / static_cast<double>(m);
  }
  size_t segments = 0;
  std::vector<double> seg(m);
  for (size_t start = 0; start + m <= n; start += hop) {
    for (size_t i = 0; i < m; ++i) seg[i] = x[start + i] * w[i];
    const auto spec = realFft(seg);
    for (size_t k = 0; k < spec.size(); ++k) {
      const bool edge = k == 0 || (m % 2 == 0 && k == m / 2);
      s.value[k] += (edge ? 1.0 : 2.0) * std::norm(spec[k]) / (fs_hz * wpow);
    }
    ++segments;
  }
  for (double& v : s.value) v /= static_cast<double>(segments);
  return s;
}

}  // namespace railvib::signal
