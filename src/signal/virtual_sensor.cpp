#include "railvib/signal/virtual_sensor.hpp"

#include <cmath>
#include <stdexcept>

#include "railvib/common/site.hpp"

namespace railvib::signal {

namespace {
MonitorSpec monitorSpecFor(const VirtualSensorSpec& spec) {
  MonitorSpec m;
  m.fs_hz = spec.output_rate_hz;
  m.components = 3;
  return m;
}
}  // namespace

VirtualSensorConfig loadVirtualSensorConfig(const ConfigNode& root) {
  const ConfigNode section = root.section("virtual_sensors");
  VirtualSensorConfig config;
  config.sample_rate_hz = section.number("sample_rate_hz", Range::closed(10.0, 100000.0));
  config.metrics_rate_hz = section.number("metrics_rate_hz", Range::closed(0.1, 1000.0));
  if (config.metrics_rate_hz > config.sample_rate_hz) section.fail("metrics_rate_hz", "must not exceed sample_rate_hz");
  config.include_gravity = section.flag("include_gravity");
  config.night = section.choice("din4150_2_period", {"day", "night"}) == "night";
  const double noise = section.number("noise_rms_m_s2", Range::nonNegative());
  const long seed = section.integer("noise_seed", 0, 0x7fffffffL);
  for (const ConfigNode& s : section.sectionList("sensors")) {
    VirtualSensorSetup setup;
    setup.spec.name = s.text("name");
    setup.spec.output_rate_hz = config.sample_rate_hz;
    setup.spec.noise_rms_m_s2 = s.number("noise_rms_m_s2", Range::nonNegative(), noise);
    // Each sensor its own reproducible noise: seed + position in the list.
    setup.spec.noise_seed = static_cast<uint64_t>(seed) + config.sensors.size();
    if (placesItsSensor(s)) {
      // Placed by its position (loadPlacedSensors): its kind says where it stands, it reads its own point.
      setup.kind = sensorKindFromName(s.choice("kind", {"free_field", "foundation", "floor"}));
      setup.source = setup.kind == SensorKind::FreeField ? "soil" : "building";
      setup.point = s.text("point", setup.spec.name);
    } else {
      setup.source = s.choice("source", {"soil", "building"});
      setup.point = s.text("point");
      setup.kind = sensorKindFromName(
          s.choice("kind", {"free_field", "foundation", "floor"}, setup.source == "soil" ? "free_field" : "floor"));
    }
    if (setup.source == "building" && setup.kind == SensorKind::FreeField) {
      s.fail("kind", "a sensor in the house stands on its foundation or a floor, not in the free field");
    }
    for (const auto& other : config.sensors) {
      if (other.spec.name == setup.spec.name) s.fail("name", "duplicate sensor name");
    }
    config.sensors.push_back(setup);
  }
  return config;
}

VirtualSensor::VirtualSensor(const VirtualSensorSpec& spec, double t0_s)
    : spec_(spec),
      t0_s_(t0_s),
      differentiator_(spec.output_rate_hz, 3, t0_s),
      monitor_(monitorSpecFor(spec)),
      rng_(spec.noise_seed) {
  if (!(spec.output_rate_hz > 0.0) || spec.output_rate_hz > spec.input_rate_hz * (1.0 + 1e-12)) {
    throw std::invalid_argument("virtual sensor " + spec.name + ": output rate must be in (0, input rate]");
  }
  if (!(spec.noise_rms_m_s2 >= 0.0)) throw std::invalid_argument("virtual sensor " + spec.name + ": noise < 0");
  if (std::abs(spec.output_rate_hz - spec.input_rate_hz) > 1e-9 * spec.input_rate_hz) {
    DecimatorSpec d;
    d.input_rate_hz = spec.input_rate_hz;
    d.output_rate_hz = spec.output_rate_hz;
    decimator_ = std::make_unique<Decimator>(d, 3, t0_s);
  }
}

size_t VirtualSensor::push(const double* velocity_m_s, size_t frames, std::vector<SensorSample>& out) {
  scratch_.clear();
  if (decimator_) {
    decimator_->push(velocity_m_s, frames, scratch_);
  } else {
    scratch_.assign(velocity_m_s, velocity_m_s + 3 * frames);
  }
  return drain(scratch_, false, out);
}

size_t VirtualSensor::flush(std::vector<SensorSample>& out) {
  scratch_.clear();
  if (decimator_) decimator_->flush(scratch_);
  return drain(scratch_, true, out);
}

size_t VirtualSensor::drain(std::vector<double>& resampled, bool flushing, std::vector<SensorSample>& out) {
  const size_t frames = resampled.size() / 3;
  if (frames > 0) monitor_.process(resampled.data(), frames);
  velocity_queue_.insert(velocity_queue_.end(), resampled.begin(), resampled.end());
  accel_.clear();
  differentiator_.push(resampled.data(), frames, accel_);
  if (flushing) differentiator_.flush(accel_);
  const size_t ready = accel_.size() / 3;
  for (size_t k = 0; k < ready; ++k) {
    SensorSample s;
    s.index = emitted_;
    s.time_s = t0_s_ + static_cast<double>(emitted_) / spec_.output_rate_hz;
    for (int c = 0; c < 3; ++c) {
      s.velocity_m_s[c] = velocity_queue_.front();
      velocity_queue_.pop_front();
      s.acceleration_m_s2[c] =
          accel_[3 * k + c] + (spec_.noise_rms_m_s2 > 0.0 ? spec_.noise_rms_m_s2 * noise_(rng_) : 0.0);
    }
    out.push_back(s);
    ++emitted_;
  }
  return ready;
}

}  // namespace railvib::signal
