#include <gtest/gtest.h>

#include <cmath>

#include "railvib/signal/virtual_sensor.hpp"

using railvib::signal::SensorSample;
using railvib::signal::VirtualSensor;
using railvib::signal::VirtualSensorSpec;

namespace {
// Vertical velocity v = V sin(2 pi f t): the sensor must report a = 2 pi f V cos(2 pi f t).
std::vector<SensorSample> runSine(const VirtualSensorSpec& spec, double f_hz, double amplitude_m_s, double duration_s,
                                  size_t block) {
  VirtualSensor sensor(spec);
  std::vector<SensorSample> out;
  const size_t n = static_cast<size_t>(duration_s * spec.input_rate_hz) + 1;
  std::vector<double> frames;
  for (size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / spec.input_rate_hz;
    frames.insert(frames.end(), {0.0, 0.0, amplitude_m_s * std::sin(2 * M_PI * f_hz * t)});
    if (frames.size() == 3 * block || i + 1 == n) {
      sensor.push(frames.data(), frames.size() / 3, out);
      frames.clear();
    }
  }
  sensor.flush(out);
  return out;
}
}  // namespace

TEST(VirtualSensor, ResamplesAndDifferentiatesASineExactlyInTime) {
  VirtualSensorSpec spec;
  spec.input_rate_hz = 4000.0;
  spec.output_rate_hz = 1000.0;
  const double f = 20.0, v = 1e-3;
  const auto out = runSine(spec, f, v, 2.0, 137);
  ASSERT_EQ(out.size(), 2001u);  // every output time <= last input time, none lost
  double max_v_err = 0.0, max_a_err = 0.0;
  for (const auto& s : out) {
    EXPECT_DOUBLE_EQ(s.time_s, static_cast<double>(s.index) / 1000.0);
    if (s.time_s < 0.1 || s.time_s > 1.9) continue;  // away from the record ends
    const double w = 2 * M_PI * f;
    max_v_err = std::max(max_v_err, std::abs(s.velocity_m_s[2] - v * std::sin(w * s.time_s)));
    max_a_err = std::max(max_a_err, std::abs(s.acceleration_m_s2[2] - w * v * std::cos(w * s.time_s)));
  }
  EXPECT_LT(max_v_err, 1e-3 * v);                 // decimator pass band, exact time alignment
  EXPECT_LT(max_a_err, 2e-3 * 2 * M_PI * f * v);  // differentiator pass-band accuracy
}

TEST(VirtualSensor, NoiseFloorHasTheRequestedRmsAndIsReproducible) {
  VirtualSensorSpec spec;
  spec.input_rate_hz = spec.output_rate_hz = 1000.0;
  spec.noise_rms_m_s2 = 0.01;
  spec.noise_seed = 42;
  const auto a = runSine(spec, 10.0, 0.0, 20.0, 500);
  const auto b = runSine(spec, 10.0, 0.0, 20.0, 77);
  ASSERT_EQ(a.size(), b.size());
  double sum_sq = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    sum_sq += a[i].acceleration_m_s2[0] * a[i].acceleration_m_s2[0];
    EXPECT_EQ(a[i].acceleration_m_s2[2], b[i].acceleration_m_s2[2]);  // same seed, any block size
  }
  const double rms = std::sqrt(sum_sq / static_cast<double>(a.size()));
  // The rms estimate of N Gaussian samples has a relative standard deviation 1/sqrt(2N): allow 4 of them.
  EXPECT_NEAR(rms, 0.01, 0.01 * 4.0 / std::sqrt(2.0 * static_cast<double>(a.size())));
}

TEST(VirtualSensor, RefusesUpsampling) {
  VirtualSensorSpec spec;
  spec.input_rate_hz = 500.0;
  spec.output_rate_hz = 1000.0;
  EXPECT_THROW(VirtualSensor{spec}, std::invalid_argument);
}
