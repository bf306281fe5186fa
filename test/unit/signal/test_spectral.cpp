// One-third-octave levels, spectra, differentiator, IIR designs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "railvib/common/constants.hpp"
#include "railvib/signal/differentiator.hpp"
#include "railvib/signal/filter_design.hpp"
#include "railvib/signal/spectrum.hpp"
#include "railvib/signal/third_octave.hpp"

using namespace railvib::signal;
using railvib::kPi;

TEST(ThirdOctave, NominalBands) {
  const auto b = thirdOctaveBands(1.0, 100.0);
  ASSERT_EQ(b.size(), 21u);
  EXPECT_DOUBLE_EQ(b.front().nominal_hz, 1.0);
  EXPECT_DOUBLE_EQ(b.back().nominal_hz, 100.0);
  EXPECT_DOUBLE_EQ(thirdOctaveNominal(15), 31.5);
  EXPECT_DOUBLE_EQ(thirdOctaveNominal(-1), 0.8);
  EXPECT_NEAR(b[15].centre_hz, 31.6228, 1e-4);
  EXPECT_NEAR(b[15].upper_hz / b[15].lower_hz, std::pow(10.0, 0.1), 1e-12);
  // The 0.45 fs limit drops bands near Nyquist.
  EXPECT_EQ(thirdOctaveBands(1.0, 400.0, 1000.0).back().nominal_hz, 400.0);
  EXPECT_EQ(thirdOctaveBands(1.0, 500.0, 1000.0).back().nominal_hz, 400.0);
}

// A 1 mm/s rms sine at a band centre reads 120.0 dB re 1e-9 m/s in its band.
TEST(ThirdOctave, PureToneLevel) {
  for (const double fs : {1000.0, 2000.0}) {
    const auto bands = thirdOctaveBands(1.0, 200.0, fs);
    for (const size_t ib : {size_t{5}, size_t{12}, size_t{15}, size_t{19}}) {  // 3.15, 16, 31.5, 80 Hz
      const double fc = bands[ib].centre_hz;
      const double amp = 1e-3 * std::sqrt(2.0);
      const size_t n = static_cast<size_t>(20.0 * fs);
      std::vector<double> v(n);
      for (size_t i = 0; i < n; ++i) v[i] = amp * std::sin(2 * kPi * fc * i / fs);
      const auto l = thirdOctaveLevels(v, fs, bands, kVelocityRefIso1683, 10.0);
      EXPECT_NEAR(l[ib], 120.0, 0.1) << "band " << bands[ib].nominal_hz << " fs " << fs;
      // Two bands away: at least 25 dB lower (6th-order Butterworth: ~ -30 dB).
      EXPECT_LT(l[ib + 2], 120.0 - 25.0);
      EXPECT_LT(l[ib - 2], 120.0 - 25.0);
      if (fs == 1000.0 && ib == 15) {
        std::printf(
            "1/3 oct 31.5 Hz band, 1 mm/s rms tone at 31.62 Hz: %.3f dB; bands -2/-1/+1/+2: %.1f %.1f %.1f %.1f\n",
            l[ib], l[ib - 2], l[ib - 1], l[ib + 1], l[ib + 2]);
      }
      // With v_ref = 5e-8 m/s the level is 20 log10(50) = 33.98 dB lower.
      const auto l5 = thirdOctaveLevels(v, fs, bands, kVelocityRef5e8, 10.0);
      EXPECT_NEAR(l[ib] - l5[ib], 20.0 * std::log10(50.0), 1e-9);
    }
  }
}

TEST(ThirdOctave, BandEdgesMinus3dBAndRunningLevel) {
  const double fs = 1000.0;
  const auto bands = thirdOctaveBands(10.0, 100.0, fs);
  ThirdOctaveAnalyzer a(fs, bands, 0.5);
  for (size_t i = 0; i < bands.size(); ++i) {
    EXPECT_NEAR(20 * std::log10(a.bandResponse(i, bands[i].lower_hz)), -3.01, 0.02);
    EXPECT_NEAR(20 * std::log10(a.bandResponse(i, bands[i].upper_hz)), -3.01, 0.02);
    EXPECT_NEAR(a.bandResponse(i, bands[i].centre_hz), 1.0, 1e-3);
  }
  // Running level of a steady tone settles to the same 120 dB.
  const double fc = bands[5].centre_hz;  // 31.5
  for (size_t i = 0; i < 8000; ++i) a.process(1e-3 * std::sqrt(2.0) * std::sin(2 * kPi * fc * i / fs));
  EXPECT_NEAR(a.runningLevelsDb()[5], 120.0, 0.15);
}

TEST(Spectrum, SineAmplitudeAndParseval) {
  const double fs = 1024.0;
  const size_t n = 4096;
  std::vector<double> x(n);
  for (size_t i = 0; i < n; ++i) x[i] = 2.5 * std::sin(2 * kPi * 64.0 * i / fs) + 0.5;
  const auto s = amplitudeSpectrum(x, fs, Window::Hann);
  EXPECT_NEAR(s.frequency_hz[256], 64.0, 1e-12);
  EXPECT_NEAR(s.value[256], 2.5, 1e-9);
  EXPECT_NEAR(s.value[0], 0.5, 1e-9);
  // Flat top: a tone between lines keeps its amplitude within 0.1 %.
  std::vector<double> y(n);
  for (size_t i = 0; i < n; ++i) y[i] = std::sin(2 * kPi * 64.125 * i / fs);
  const auto ft = amplitudeSpectrum(y, fs, Window::FlatTop);
  double mx = 0.0;
  for (double v : ft.value) mx = std::max(mx, v);
  EXPECT_NEAR(mx, 1.0, 2e-3);
  // PSD integral equals the mean square (white noise, Welch).
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 0.7);
  std::vector<double> w(1 << 16);
  for (double& v : w) v = g(rng);
  double ms = 0.0;
  for (double v : w) ms += v * v;
  ms /= static_cast<double>(w.size());
  const auto p = powerSpectralDensity(w, fs, 1024);
  double integral = 0.0;
  for (double v : p.value) integral += v * (fs / 1024.0);
  EXPECT_NEAR(integral / ms, 1.0, 0.03);
  // Round trip.
  const auto back = inverseRealFft(realFft(x), n);
  for (size_t i = 0; i < n; ++i) ASSERT_NEAR(back[i], x[i], 1e-12);
}

TEST(Differentiator, SineDerivativeAndAlignment) {
  const double fs = 1000.0;
  Differentiator d(fs, 2, 0.25);
  for (double f = 0.1; f <= 400.0; f += 3.0) EXPECT_NEAR(d.relativeResponse(f), 1.0, 1e-4) << f;
  // Two channels, sines at 0.02 fs and 0.3 fs, pushed in odd blocks.
  const size_t n = 3000;
  std::vector<double> x(2 * n), out;
  const double f1 = 20.0, f2 = 300.0;
  for (size_t i = 0; i < n; ++i) {
    const double t = 0.25 + i / fs;
    x[2 * i] = std::sin(2 * kPi * f1 * t);
    x[2 * i + 1] = std::cos(2 * kPi * f2 * t);
  }
  for (size_t pos = 0; pos < n; pos += 37) d.push(x.data() + 2 * pos, std::min<size_t>(37, n - pos), out);
  d.flush(out);
  ASSERT_EQ(out.size(), 2 * n);
  double e1 = 0.0, e2 = 0.0;
  for (size_t i = 50; i + 50 < n; ++i) {
    const double t = d.outputTime(i);
    e1 = std::max(e1, std::abs(out[2 * i] - 2 * kPi * f1 * std::cos(2 * kPi * f1 * t)) / (2 * kPi * f1));
    e2 = std::max(e2, std::abs(out[2 * i + 1] + 2 * kPi * f2 * std::sin(2 * kPi * f2 * t)) / (2 * kPi * f2));
  }
  EXPECT_LT(e1, 1e-3);
  EXPECT_LT(e2, 1e-3);
  std::printf("differentiator latency %zu samples; relative error 20 Hz %.1e, 300 Hz %.1e (fs 1 kHz)\n",
              d.latencySamples(), e1, e2);
  // Integration undoes it.
  std::vector<double> c(n);
  for (size_t i = 0; i < n; ++i) c[i] = 2 * kPi * f1 * std::cos(2 * kPi * f1 * i / fs);
  const auto s = integrateTrapezoid(c, fs);
  EXPECT_NEAR(s[n / 2 + 3], std::sin(2 * kPi * f1 * (n / 2 + 3) / fs), 2e-3);
}

TEST(FilterDesign, ButterworthCornersAndMatching) {
  const double fs = 1000.0;
  const auto lp = butterworthLowpass(2, 100.0, fs);
  EXPECT_NEAR(std::abs(lp.response(100.0, fs)), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(std::abs(lp.response(0.0, fs)), 1.0, 1e-12);
  const auto lpm = butterworthLowpass(2, 100.0, fs, 80.0);
  EXPECT_NEAR(std::abs(lpm.response(80.0, fs)), 1.0 / std::sqrt(1.0 + std::pow(0.8, 4)), 1e-12);
  const auto hp = butterworthHighpass(3, 5.0, fs);
  EXPECT_NEAR(std::abs(hp.response(5.0, fs)), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(std::abs(hp.response(400.0, fs)), 1.0, 1e-6);
  const auto h1 = firstOrderHighpass(5.6, fs);
  EXPECT_NEAR(std::abs(h1.response(5.6, fs)), std::sqrt(0.5), 1e-12);
}
