// Decimator / StreamInterpolator: pass band, stop band, exact time alignment,
// block-size independence, interpolation accuracy.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "railvib/common/constants.hpp"
#include "railvib/signal/decimator.hpp"

using namespace railvib::signal;
using railvib::kPi;

namespace {

std::vector<double> sine(double f, double fs, size_t n, double t0 = 0.0, double phase = 0.3) {
  std::vector<double> x(n);
  for (size_t i = 0; i < n; ++i) x[i] = std::sin(2.0 * kPi * f * (t0 + static_cast<double>(i) / fs) + phase);
  return x;
}
}  // namespace

TEST(Decimator, DesignFiguresIntegerRatio) {
  Decimator d({100000.0, 2000.0, 0.4, 70.0}, 1);
  EXPECT_EQ(d.integerRatio(), 50);
  EXPECT_EQ(d.taps().size(), 2 * d.latencyInputSamples() + 1);
  // Pass band flat within 0.1 dB up to 0.4 * 2000 = 800 Hz.
  double worst_pass_db = 0.0;
  for (double f = 0.0; f <= 800.0; f += 5.0) {
    worst_pass_db = std::max(worst_pass_db, std::abs(20.0 * std::log10(d.responseMagnitude(f))));
  }
  EXPECT_LT(worst_pass_db, 0.1);
  // Stop band >= 60 dB from the output Nyquist (1000 Hz) up to the input Nyquist.
  double worst_stop = 0.0;
  for (double f = 1000.0; f <= 50000.0; f += 7.3) worst_stop = std::max(worst_stop, d.responseMagnitude(f));
  EXPECT_LT(20.0 * std::log10(worst_stop), -60.0);
  ASSERT_EQ(d.stageCount(), 2u);  // the cheaper split is chosen
  std::printf(
      "decimator 100k->2k: stages %d x %d, equivalent taps %zu, latency %zu samples (%.3f ms), pass ripple %.4f dB, "
      "stop %.1f dB\n",
      d.stageRatios()[0], d.stageRatios()[1], d.taps().size(), d.latencyInputSamples(), 1e3 * d.halfWidthSeconds(),
      worst_pass_db, 20.0 * std::log10(worst_stop));
}

TEST(Decimator, DesignFiguresFractionalRatio) {
  Decimator d({8333.3, 1000.0, 0.4, 70.0}, 1);
  EXPECT_EQ(d.integerRatio(), 0);
  double worst_pass_db = 0.0;
  for (double f = 0.0; f <= 400.0; f += 2.0) {
    worst_pass_db = std::max(worst_pass_db, std::abs(20.0 * std::log10(d.responseMagnitude(f))));
  }
  EXPECT_LT(worst_pass_db, 0.1);
  double worst_stop = 0.0;
  for (double f = 500.0; f <= 4166.0; f += 1.7) worst_stop = std::max(worst_stop, d.responseMagnitude(f));
  EXPECT_LT(20.0 * std::log10(worst_stop), -60.0);
}

// A pass-band sine decimated: each output equals the sine at t0 + k / fo.
TEST(Decimator, TimeAlignmentExactIntegerAndFractional) {
  for (const double fi : {100000.0, 8333.3}) {
    const double fo = fi > 50000.0 ? 2000.0 : 1000.0;
    const double f = 0.37 * fo;  // inside the pass band
    const double t0 = 0.0123;
    Decimator d({fi, fo, 0.4, 70.0}, 1, t0);
    const size_t n = static_cast<size_t>(0.5 * fi);
    const auto x = sine(f, fi, n, t0);
    std::vector<double> y;
    d.push(x, y);
    // Skip the start-up (first value held before t0) and compare the rest.
    const size_t skip = static_cast<size_t>(std::ceil(d.halfWidthSeconds() * fo)) + 1;
    ASSERT_GT(y.size(), skip + 100);
    double worst = 0.0;
    for (size_t k = skip; k < y.size(); ++k) {
      const double t = d.outputTime(k);
      const double ref = std::sin(2.0 * kPi * f * t + 0.3);
      worst = std::max(worst, std::abs(y[k] - ref));
    }
    EXPECT_LT(worst, 1e-3) << "fi = " << fi;
    std::printf("decimator %.1f->%.0f Hz, sine at %.1f Hz: max |y - sin(t_k)| = %.2e\n", fi, fo, f, worst);
  }
}

TEST(Decimator, StopBandSineAttenuated) {
  Decimator d({100000.0, 2000.0, 0.4, 70.0}, 1);
  std::vector<double> y;
  d.push(sine(1000.0, 100000.0, 100000), y);  // exactly at the output Nyquist
  double peak = 0.0;
  for (size_t k = 50; k + 50 < y.size(); ++k) peak = std::max(peak, std::abs(y[k]));
  EXPECT_LT(20.0 * std::log10(peak), -60.0);
}

TEST(Decimator, LatencyAndCounts) {
  Decimator d({100000.0, 2000.0}, 2);
  const size_t lat = d.latencyInputSamples();
  std::vector<double> y;
  std::vector<double> frames(2 * (lat + 1), 1.0);
  // Output 0 (time t0) needs inputs up to index lat.
  EXPECT_EQ(d.push(frames.data(), lat, y), 0u);
  EXPECT_EQ(d.push(frames.data() + 2 * lat, 1, y), 1u);
  EXPECT_EQ(d.outputCount(), 1u);
  // flush: outputs for every time <= the last input time, padded with the last value.
  Decimator e({100000.0, 2000.0}, 1);
  std::vector<double> x(1234, 2.5), z;
  e.push(x, z);
  e.flush(z);
  EXPECT_EQ(z.size(), (1234 - 1) / 50 + 1u);
  for (double v : z) EXPECT_NEAR(v, 2.5, 1e-12);
}

TEST(Decimator, BlockSizeIndependentMultiChannel) {
  const size_t nc = 3;
  const size_t n = 40000;
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n * nc);
  for (double& v : x) v = g(rng);
  for (const double fo : {2000.0, 1300.0}) {
    Decimator one({100000.0, fo}, nc, 0.5);
    std::vector<double> ref;
    one.push(x, ref);
    one.flush(ref);
    Decimator many({100000.0, fo}, nc, 0.5);
    std::vector<double> out;
    std::uniform_int_distribution<size_t> bs(0, 3000);
    size_t pos = 0;
    uint64_t expected_index = 0;
    while (pos < n) {
      const size_t b = std::min(n - pos, bs(rng));
      EXPECT_EQ(many.outputCount(), expected_index);
      expected_index += many.push(x.data() + pos * nc, b, out);
      pos += b;
    }
    many.flush(out);
    ASSERT_EQ(out.size(), ref.size());
    for (size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], ref[i]) << i;
    EXPECT_EQ(out.size() / nc, static_cast<size_t>(std::floor((n - 1) * fo / 100000.0 + 1e-9)) + 1);
  }
}

TEST(StreamInterpolator, BandLimitedSignalAccuracy) {
  const double fs = 2000.0;
  const double t0 = -0.01;
  // Sum of tones up to 100 Hz (loads content) and one at 0.35 fs for the sinc kernel.
  auto sig = [](double t, bool hf) {
    double v = std::sin(2 * kPi * 23.0 * t) + 0.5 * std::cos(2 * kPi * 71.0 * t + 1.0);
    if (hf) v += 0.2 * std::sin(2 * kPi * 700.0 * t + 0.2);
    return v;
  };
  for (const auto kind : {InterpolationKind::Cubic, InterpolationKind::WindowedSinc}) {
    const bool hf = kind == InterpolationKind::WindowedSinc;
    StreamInterpolator ip(fs, 1, t0, kind);
    std::vector<double> block;
    double worst = 0.0;
    double t = 0.0;
    const double dt = 1.37e-4;  // a soil step, not a divisor of 1/fs
    for (int b = 0; b < 200; ++b) {
      block.clear();
      for (int i = 0; i < 10; ++i) block.push_back(sig(t0 + (b * 10 + i) / fs, hf));
      ip.push(block);
      while (ip.canEvaluate(t)) {
        worst = std::max(worst, std::abs(ip.evaluate(t)[0] - sig(t, hf)));
        ip.discardBefore(t);
        t += dt;
      }
    }
    ip.finish();
    EXPECT_TRUE(ip.canEvaluate(10.0));
    const double tol = hf ? 2e-3 : 2e-3;
    EXPECT_LT(worst, tol);
    std::printf("interpolator %s: max error %.2e (signal amplitude ~1.5)\n", hf ? "sinc(16)" : "cubic", worst);
  }
}

TEST(Decimator, RefusesBadInputAndHandlesEdges) {
  EXPECT_THROW(Decimator({1000.0, 2000.0}, 1), std::invalid_argument);  // up-sampling
  EXPECT_THROW(Decimator({1000.0, 0.0}, 1), std::invalid_argument);
  EXPECT_THROW(Decimator({1000.0, 100.0, 0.6}, 1), std::invalid_argument);
  EXPECT_THROW(Decimator({1000.0, 100.0}, 0), std::invalid_argument);
  Decimator same({1000.0, 1000.0}, 2);  // ratio 1: identity, no latency
  EXPECT_EQ(same.latencyInputSamples(), 0u);
  std::vector<double> x{1, 2, 3, 4, 5, 6}, y;
  EXPECT_EQ(same.push(x, y), 3u);
  EXPECT_EQ(y, x);
  Decimator empty({1000.0, 100.0}, 1);
  std::vector<double> z;
  EXPECT_EQ(empty.flush(z), 0u);
  EXPECT_THROW(empty.push(x, z), std::logic_error);
}

TEST(StreamInterpolator, AvailabilityAndHold) {
  StreamInterpolator ip(100.0, 1, 1.0);
  EXPECT_FALSE(ip.canEvaluate(0.0));
  std::vector<double> x(10, 3.0);
  ip.push(x);
  EXPECT_NEAR(ip.availableUntil(), 1.0 + 7.0 / 100.0, 1e-12);
  EXPECT_NEAR(ip.evaluate(0.5)[0], 3.0, 1e-12);  // before t0: first value held
  EXPECT_THROW(ip.evaluate(1.08), std::out_of_range);
  ip.finish();
  EXPECT_NEAR(ip.evaluate(5.0)[0], 3.0, 1e-12);  // after the end: last value held
  ip.discardBefore(1.05);
  EXPECT_THROW(ip.evaluate(1.0), std::out_of_range);
}
