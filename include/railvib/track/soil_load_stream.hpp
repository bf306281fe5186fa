// railvib/track: the track as a stream processor, for the track node.
//
// In: contact-force samples at the step rate 1/dt (per sample and wheel: the
// position along the track and the force, N, compression positive = downward
// on the rail). Sample n stands for time n dt. Sample 0 sets the initial state
// (static equilibrium under its loads); every later sample is the load at the
// end of one Newmark step. Out: ballast-to-soil loads per sleeper, BOTH rails
// (2 x half track, N, downward), anti-alias decimated to `rate_hz` by
// railvib::signal::Decimator; output sample k stands for time k / rate_hz,
// frames interleaved [sample][sleeper]. Wheels outside the rail are ignored
// (counted). No ROS here; the node only moves samples in and out.
//
// Header-only on purpose: the track library does not link the signal library;
// whoever uses this class links the whole core (railvib_core).
#pragma once

#include <memory>
#include <stdexcept>
#include <vector>

#include "railvib/signal/decimator.hpp"
#include "railvib/track/track_stepper.hpp"

namespace railvib::track {

class SoilLoadStream {
 public:
  SoilLoadStream(const TrackParams& params, double dt_s, double rate_hz)
      : stepper_(params, dt_s), rate_hz_(rate_hz) {
    if (!(rate_hz > 0.0) || rate_hz > (1.0 / dt_s) * (1.0 + 1e-9)) {
      throw std::invalid_argument("SoilLoadStream: the load rate must be in (0, 1/dt]");
    }
    signal::DecimatorSpec spec;
    spec.input_rate_hz = 1.0 / dt_s;
    spec.output_rate_hz = rate_hz;
    decimator_ = std::make_unique<signal::Decimator>(spec, static_cast<size_t>(stepper_.sleeperCount()), 0.0);
  }

  const TrackModel& model() const { return stepper_.model(); }
  const std::vector<double>& sleeperPositions() const { return stepper_.sleeperPositions(); }
  int sleeperCount() const { return stepper_.sleeperCount(); }
  double timeStep() const { return stepper_.timeStep(); }
  double loadSamplePeriod() const { return 1.0 / rate_hz_; }
  double loadSampleRate() const { return rate_hz_; }
  /// Time of the last input sample consumed (0 before the first).
  double time() const { return stepper_.time(); }
  uint64_t inputCount() const { return inputs_; }
  long ignoredLoadCount() const { return stepper_.ignoredLoadCount(); }
  /// Latency of the decimated output (s).
  double latencySeconds() const { return decimator_->halfWidthSeconds(); }
  const TrackStepper& stepper() const { return stepper_; }

  /// Consume `sample_count` samples of `wheel_count` wheels (arrays [sample][wheel]);
  /// append the completed decimated frames ([sample][sleeper]) to `out`.
  /// Returns the number of frames appended.
  size_t push(size_t sample_count, size_t wheel_count, const double* position_m, const double* force_n,
              std::vector<double>& out) {
    size_t frames = 0;
    for (size_t s = 0; s < sample_count; ++s) {
      loads_.resize(wheel_count);
      for (size_t w = 0; w < wheel_count; ++w) {
        loads_[w] = PointLoad{position_m[s * wheel_count + w], force_n[s * wheel_count + w]};
      }
      if (inputs_ == 0) {
        stepper_.start(loads_, 0.0);
      } else {
        stepper_.step(loads_);
      }
      ++inputs_;
      frames += decimator_->push(stepper_.soilLoadsBothRails().data(), 1, out);
    }
    return frames;
  }

  /// End of stream: emit the remaining decimated frames.
  size_t flush(std::vector<double>& out) { return decimator_->flush(out); }

 private:
  TrackStepper stepper_;
  double rate_hz_;
  std::unique_ptr<signal::Decimator> decimator_;
  std::vector<PointLoad> loads_;
  uint64_t inputs_ = 0;
};

}  // namespace railvib::track
