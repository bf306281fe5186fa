// railvib/signal: a virtual triaxial vibration sensor, like the field
// accelerometers at Haren. Velocity samples (m/s, 3 components, frame of the
// sensor) come in at the model's rate; the sensor band-limits and resamples
// them to its own rate (anti-alias Decimator), derives the acceleration it
// measures (band-limited Differentiator), adds its noise floor (Gaussian,
// seeded: reproducible) to the acceleration, and evaluates the vibration
// metrics (VibrationMonitor: KB_F, PPV, one-third-octave levels) on the
// velocity. Sample k of the output stands for time t0 + k / output_rate.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/signal/decimator.hpp"
#include "railvib/signal/differentiator.hpp"
#include "railvib/signal/monitor.hpp"

namespace railvib::signal {

struct VirtualSensorSpec {
  std::string name;
  double input_rate_hz = 1000.0;
  /// Sensor sample rate; <= input rate (an integer or any ratio: see Decimator).
  double output_rate_hz = 1000.0;
  /// RMS of the acceleration noise floor (m/s^2), 0 for a perfect sensor.
  double noise_rms_m_s2 = 0.0;
  uint64_t noise_seed = 1;
};

struct SensorSample {
  uint64_t index = 0;
  double time_s = 0.0;
  double velocity_m_s[3] = {0, 0, 0};
  double acceleration_m_s2[3] = {0, 0, 0};
};

/// A configured sensor: what it measures and where its input comes from.
struct VirtualSensorSetup {
  VirtualSensorSpec spec;  ///< input_rate_hz is set when the input stream is known
  std::string source;      ///< "soil" (SurfaceVelocities) or "building" (BuildingResponse)
  std::string point;       ///< name of the receiver / response point in that stream
  /// Where it stands, which decides the standards judged on it (vibration.hpp).
  SensorKind kind = SensorKind::FreeField;
};

struct VirtualSensorConfig {
  double sample_rate_hz = 1000.0;
  double metrics_rate_hz = 10.0;
  bool include_gravity = true;
  bool night = false;  ///< DIN 4150-2 period of the guide values
  std::vector<VirtualSensorSetup> sensors;
};

/// Read the `virtual_sensors` section (validated; names unique, sources soil|building; kind
/// free_field | foundation | floor, by default free_field for a soil sensor, floor for a house one).
VirtualSensorConfig loadVirtualSensorConfig(const ConfigNode& root);

class VirtualSensor {
 public:
  explicit VirtualSensor(const VirtualSensorSpec& spec, double t0_s = 0.0);

  const VirtualSensorSpec& spec() const { return spec_; }
  /// Push velocity frames (x, y, z interleaved, m/s); completed sensor samples are appended to out.
  size_t push(const double* velocity_m_s, size_t frames, std::vector<SensorSample>& out);
  /// End of the input stream: emit every remaining sample.
  size_t flush(std::vector<SensorSample>& out);
  /// Metrics of the velocity emitted so far.
  MonitorSnapshot metrics() const { return monitor_.snapshot(); }
  uint64_t samplesEmitted() const { return emitted_; }

 private:
  size_t drain(std::vector<double>& resampled, bool flushing, std::vector<SensorSample>& out);

  VirtualSensorSpec spec_;
  double t0_s_;
  std::unique_ptr<Decimator> decimator_;  // null when the rates are equal
  Differentiator differentiator_;
  VibrationMonitor monitor_;
  std::deque<double> velocity_queue_;  // resampled velocity frames awaiting their acceleration
  std::vector<double> scratch_, accel_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
  uint64_t emitted_ = 0;
};

}  // namespace railvib::signal
