// railvib/track: streaming drivers the ROS node (or a tool) wraps. No ROS here.
//
// TrackStepper: per step, contact loads (position, force, rail) in; ballast-to-soil
// loads out, at the full step rate: one per sleeper for the half track (both
// rails together), one per rail seat at full width. Decimation to the soil rate
// is the caller's job (railvib::signal::Decimator).
//
// MovingLoadSource: constant moving loads (axles) at constant speed.
#pragma once

#include <memory>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/track/track_newmark.hpp"

namespace railvib::track {

class TrackStepper {
 public:
  TrackStepper(const TrackParams& params, double dt_s);

  const TrackModel& model() const { return model_; }
  TrackNewmark& integrator() { return newmark_; }
  const TrackNewmark& integrator() const { return newmark_; }
  double timeStep() const { return newmark_.timeStep(); }
  double time() const { return newmark_.time(); }
  long stepCount() const { return newmark_.stepCount(); }
  int sleeperCount() const { return model_.sleeperCount(); }
  const std::vector<double>& sleeperPositions() const { return model_.sleeperPositions(); }

  /// Start in static equilibrium under the loads (e.g. the first sample's contact loads), at rest,
  /// or, with convection_speed_m_s != 0, in the steady state of that deflection moving with the
  /// loads (TrackNewmark::setConvectedStaticState): no start-up transient from the motion.
  void start(const std::vector<PointLoad>& initial_loads, double t0_s = 0.0, double convection_speed_m_s = 0.0);
  /// Advance one step: `loads` act at the END of the step (t + dt), positive downward.
  /// Loads outside the rail are ignored (counted in ignoredLoadCount()).
  void step(const std::vector<PointLoad>& loads);

  /// Ballast force on the foundation under each rail seat (N, downward), seat-major ([seat][sleeper],
  /// TrackNewmark::ballastForcesPerSeat; the half track has one seat), current state.
  const std::vector<double>& ballastForcesPerSeat() const { return ballast_; }
  /// What the soil receives (N, downward), current state: half track 2 x the seat per sleeper (both
  /// rails), full width each seat's force, [sleeper][seat] (soilLoadFrames, track_model.hpp).
  const std::vector<double>& soilLoads() const { return soil_; }
  /// Forces per sleeper in soilLoads(): 1 (half track) or 2 (full width).
  int soilLoadsPerSleeper() const { return model_.railCount(); }
  long ignoredLoadCount() const { return ignored_; }

 private:
  void updateOutputs();
  TrackModel model_;
  TrackNewmark newmark_;
  std::vector<PointLoad> buffer_;
  std::vector<double> ballast_, soil_;
  long ignored_ = 0;
};

/// Constant vertical loads moving at constant speed: load k at x = front_start + speed * t - offset_k,
/// on rails[k] (empty: all on the left rail, the half track's).
struct MovingLoadSource {
  double front_start_m = 0.0;
  double speed_m_s = 0.0;
  std::vector<double> offsets_behind_m;  ///< wheel k at x = front - offset_k
  std::vector<double> forces_n;          ///< per wheel (N, downward)
  std::vector<Rail> rails;               ///< per wheel, or empty

  std::vector<PointLoad> loadsAt(double t_s) const;
};

}  // namespace railvib::track
