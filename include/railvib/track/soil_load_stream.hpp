// railvib/track: the track as a stream processor, contact-force samples in,
// ballast-to-soil load samples out at the soil's rate. This is the whole
// computation of the track node; the node only moves messages.
//
// Contact sample i stands for time i * dt (i = 0 is t = 0). Sample 0 sets the
// static equilibrium the run starts from (at rest, or convected with the
// loads; no start-up transient); each later
// sample advances the Newmark integrator by one step with the loads acting at
// the end of the step. The per-step soil loads (N, downward positive; half
// track: one per sleeper, 2 x the rail seat; full width: one per rail seat,
// [sleeper][seat]: TrackStepper::soilLoads) go through the anti-alias decimator of
// railvib/signal, whose output sample k stands for time k / load_rate exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "railvib/signal/decimator.hpp"
#include "railvib/track/track_stepper.hpp"

namespace railvib::track {

class SoilLoadStream {
 public:
  /// load_sample_rate_hz must divide 1/dt_s into an integer ratio >= 1. start_convection_speed_m_s:
  /// see TrackStepper::start (the vehicle's simulation.convected_track_start uses the run's speed).
  SoilLoadStream(const TrackParams& params, double dt_s, double load_sample_rate_hz,
                 double start_convection_speed_m_s = 0.0);

  /// Push contact samples, row-major [sample][wheel]: positions (m) and forces (N, compression
  /// positive); wheel w runs on wheel_rails[w] (the half track: Rail::Left only), wheel_rails.size()
  /// wheels per sample. Completed soil-load frames (soilLoadsPerFrame() values each: [sleeper] or
  /// [sleeper][seat]) are appended to `out`; returns their count.
  size_t push(size_t sample_count, const std::vector<Rail>& wheel_rails, const double* position_m,
              const double* force_n, std::vector<double>& out);
  /// End of the contact stream: emit the remaining soil-load samples.
  size_t flush(std::vector<double>& out);

  int sleeperCount() const { return stepper_.sleeperCount(); }
  /// Forces per sleeper in a soil-load frame: 1 (half track) or 2 (full width, left and right seat).
  int soilLoadsPerSleeper() const { return stepper_.soilLoadsPerSleeper(); }
  size_t soilLoadsPerFrame() const {
    return static_cast<size_t>(stepper_.sleeperCount()) * static_cast<size_t>(stepper_.soilLoadsPerSleeper());
  }
  const std::vector<double>& sleeperPositions() const { return stepper_.sleeperPositions(); }
  double timeStep() const { return stepper_.timeStep(); }
  double loadSamplePeriod() const { return 1.0 / decimator_.outputRate(); }
  uint64_t contactSamplesConsumed() const { return contact_samples_; }
  uint64_t loadSamplesEmitted() const { return decimator_.outputCount(); }
  /// Simulated time of the last contact sample consumed (s).
  double time() const { return stepper_.time(); }
  const TrackStepper& stepper() const { return stepper_; }

 private:
  TrackStepper stepper_;
  signal::Decimator decimator_;
  std::vector<PointLoad> loads_;
  uint64_t contact_samples_ = 0;
  double start_convection_speed_m_s_ = 0.0;
};

}  // namespace railvib::track
