#include "railvib/track/soil_load_stream.hpp"

#include <cmath>
#include <stdexcept>

namespace railvib::track {

namespace {
signal::DecimatorSpec loadDecimatorSpec(double dt_s, double load_rate_hz) {
  const double input_rate = 1.0 / dt_s;
  const double ratio = input_rate / load_rate_hz;
  if (!(ratio >= 1.0) || std::abs(ratio - std::round(ratio)) > 1e-6 * ratio) {
    throw std::invalid_argument("soil load rate " + std::to_string(load_rate_hz) +
                                " Hz must divide the track step rate " + std::to_string(input_rate) +
                                " Hz into an integer ratio");
  }
  signal::DecimatorSpec spec;
  spec.input_rate_hz = input_rate;
  spec.output_rate_hz = input_rate / std::round(ratio);
  return spec;
}
}  // namespace

SoilLoadStream::SoilLoadStream(const TrackParams& params, double dt_s, double load_sample_rate_hz,
                               double start_convection_speed_m_s)
    : stepper_(params, dt_s),
      decimator_(loadDecimatorSpec(dt_s, load_sample_rate_hz), soilLoadsPerFrame()),
      start_convection_speed_m_s_(start_convection_speed_m_s) {}

size_t SoilLoadStream::push(size_t sample_count, const std::vector<Rail>& wheel_rails, const double* position_m,
                            const double* force_n, std::vector<double>& out) {
  size_t emitted = 0;
  const size_t wheel_count = wheel_rails.size();
  loads_.resize(wheel_count);
  for (size_t w = 0; w < wheel_count; ++w) loads_[w].rail = wheel_rails[w];
  for (size_t s = 0; s < sample_count; ++s) {
    for (size_t w = 0; w < wheel_count; ++w) {
      loads_[w].x_m = position_m[s * wheel_count + w];
      loads_[w].force_n = force_n[s * wheel_count + w];
    }
    if (contact_samples_ == 0) {
      stepper_.start(loads_, 0.0, start_convection_speed_m_s_);
    } else {
      stepper_.step(loads_);
    }
    ++contact_samples_;
    emitted += decimator_.push(stepper_.soilLoads().data(), 1, out);
  }
  return emitted;
}

size_t SoilLoadStream::flush(std::vector<double>& out) { return decimator_.flush(out); }

}  // namespace railvib::track
