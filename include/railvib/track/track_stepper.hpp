// railvib/track: streaming drivers the ROS node (or a tool) wraps. No ROS here.
//
// TrackStepper: per step, contact loads (position, force) in; ballast-to-soil
// loads per sleeper out, at the full step rate. Decimation to the soil rate is
// the caller's job (railvib::signal::Decimator).
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

  /// Ballast force on the foundation per sleeper, half track (N, downward), current state.
  const std::vector<double>& ballastForcesHalfTrack() const { return ballast_; }
  /// Both rails: 2 x half track (what the soil receives).
  const std::vector<double>& soilLoadsBothRails() const { return soil_; }
  long ignoredLoadCount() const { return ignored_; }

 private:
  void updateOutputs();
  TrackModel model_;
  TrackNewmark newmark_;
  std::vector<PointLoad> buffer_;
  std::vector<double> ballast_, soil_;
  long ignored_ = 0;
};

/// Constant vertical loads moving at constant speed: load k at x = x0 + offset_k + speed * t.
struct MovingLoadSource {
  double front_start_m = 0.0;
  double speed_m_s = 0.0;
  std::vector<double> offsets_behind_m;  ///< axle k at x = front - offset_k
  std::vector<double> forces_n;          ///< per axle and rail (N, downward)

  std::vector<PointLoad> loadsAt(double t_s) const;
};

}  // namespace railvib::track
