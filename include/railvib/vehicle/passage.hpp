// railvib/vehicle: the coupled vehicle/rail passage, streamed block by block.
//
// Time integration: implicit Newmark (beta = 1/4, gamma = 1/2, constant dt)
// of the vehicle (dense, its reduced DOFs) and, for a flexible track, of the track
// model (railvib::track::TrackNewmark), coupled exactly at the end of each
// step through the nonlinear Hertz contact F = C_H delta^1.5 (delta > 0, else
// 0: loss of contact allowed), delta = w_wheel - w_rail + z (w downward, z
// the unevenness height, up). Both integrators are linear in the contact
// forces over a step:
//     w_wheel = w_wheel_free - G_v F,   w_rail = w_rail_free + G_r F,
// with G_v = B^T K_eff,v^{-1} B (vehicle) and G_r the rail compliance under
// unit loads at the wheel points (K_eff,track^{-1} back-substitutions).
// Newton on the few wheel forces solves F = C_H max(d_free - (G_v + G_r) F, 0)^1.5
// to |dF| <= tolerance * mean static wheel load (default 1e-9).
//
// The run starts from the static equilibrium of the vehicle on the (rigid or
// statically deflected flexible) track with the wheels at their t = 0
// positions: v = a = 0, no start-up transient.
//
// Streaming: sample k is the state at t = k dt; sample 0 is the static
// equilibrium. advance(n, block) appends the next n samples (first_index =
// index of the first one), so consecutive blocks are contiguous.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/unevenness.hpp"
#include "railvib/vehicle/vehicle_model.hpp"

namespace railvib::track {
class TrackNewmark;
}

namespace railvib::vehicle {

/// The rail(s) under the wheels, as the vehicle's step sees them. Each wheel stands on its own rail
/// (setWheelRails: WheelInfo::rail; the half track has the left rail only): every x_m list below is
/// one position per wheel, in the order of those rails.
class RailSupport {
 public:
  virtual ~RailSupport() = default;
  /// The rail under each wheel (default: every wheel on the left rail, the half track's).
  void setWheelRails(std::vector<track::Rail> rails) { wheel_rails_ = std::move(rails); }
  /// Rail seats per sleeper in ballastForces(): 1 (half track) or 2 (full width: left, then right).
  virtual int railSeatCount() const { return 1; }
  virtual bool isRigid() const = 0;
  /// Static compliance (m/N): rail static displacement at x_i per unit load at x_j.
  virtual Eigen::MatrixXd staticCompliance(const std::vector<double>& x_m) = 0;
  /// Start in static equilibrium under loads F_j at x_j (N, downward) moving at
  /// `speed_m_s`: the static deflection is convected with the loads (v = -V du/dx,
  /// a = V^2 d2u/dx2), which removes most of the start-up transient.
  virtual void start(const std::vector<double>& x_m, const std::vector<double>& forces_n, double t_s,
                     double speed_m_s) = 0;
  /// Prepare the step to the end-of-step wheel positions: rail displacement at
  /// the points without contact loads, and end-of-step compliance (m/N).
  virtual void prepareStep(const std::vector<double>& x_m, Eigen::VectorXd& free_displacement_m,
                           Eigen::MatrixXd& compliance_m_n) = 0;
  /// Finish the step with the contact forces (N, downward on the rail).
  virtual void commitStep(const std::vector<double>& forces_n) = 0;
  /// Ballast-to-foundation loads per rail seat and sleeper (N, downward): [seat * sleepers + s],
  /// seat 0 the left rail's (the half track's only seat), 1 the right's; empty for a rigid rail.
  virtual void ballastForces(std::vector<double>& out) const = 0;
  virtual std::vector<double> sleeperPositions() const = 0;
  /// Range of x where wheels may be (m).
  virtual double xMin() const = 0;
  virtual double xMax() const = 0;

 protected:
  /// The rail of wheel i (Left when not set or beyond the list).
  track::Rail wheelRail(size_t i) const { return i < wheel_rails_.size() ? wheel_rails_[i] : track::Rail::Left; }

 private:
  std::vector<track::Rail> wheel_rails_;
};

/// Undeformable rail.
class RigidRail : public RailSupport {
 public:
  bool isRigid() const override { return true; }
  Eigen::MatrixXd staticCompliance(const std::vector<double>& x) override;
  void start(const std::vector<double>&, const std::vector<double>&, double, double) override {}
  void prepareStep(const std::vector<double>& x, Eigen::VectorXd& free, Eigen::MatrixXd& G) override;
  void commitStep(const std::vector<double>&) override {}
  void ballastForces(std::vector<double>& out) const override { out.clear(); }
  std::vector<double> sleeperPositions() const override { return {}; }
  double xMin() const override { return -1e300; }
  double xMax() const override { return 1e300; }
};

/// Flexible track (railvib::track::TrackModel + TrackNewmark).
class FlexibleRail : public RailSupport {
 public:
  FlexibleRail(const track::TrackParams& params, double dt_s);
  ~FlexibleRail() override;
  bool isRigid() const override { return false; }
  int railSeatCount() const override;
  Eigen::MatrixXd staticCompliance(const std::vector<double>& x) override;
  void start(const std::vector<double>& x, const std::vector<double>& F, double t_s, double speed_m_s) override;
  void prepareStep(const std::vector<double>& x, Eigen::VectorXd& free, Eigen::MatrixXd& G) override;
  void commitStep(const std::vector<double>& F) override;
  void ballastForces(std::vector<double>& out) const override;
  std::vector<double> sleeperPositions() const override;
  double xMin() const override;
  double xMax() const override;
  /// The track's integrator (its state: energies, displacements) and model.
  const track::TrackNewmark& integrator() const;
  struct Impl;
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// The rail of a passage: FlexibleRail on the track model, or RigidRail (params.vehicle_track).
std::unique_ptr<RailSupport> makeRailSupport(const PassageParams& params, const track::TrackParams& track);

/// Solve F = C_H max(d_free - G F, 0)^1.5 by Newton (F in/out: initial guess
/// and result). Returns the iteration count; throws std::runtime_error if not
/// converged to max|dF| <= tol_n within 100 iterations.
int solveHertzContact(const Eigen::VectorXd& d_free, const Eigen::MatrixXd& G, double hertz_constant,
                      Eigen::VectorXd& F, double tol_n);

/// Static equilibrium of the vehicle on the rail with wheels at x (m).
struct StaticState {
  Eigen::VectorXd q;                    ///< reduced displacements (m, rad), downward
  Eigen::VectorXd contact_force_n;      ///< per wheel
  Eigen::VectorXd rail_displacement_m;  ///< rail static displacement under each wheel
  Eigen::VectorXd compression_m;        ///< Hertz compression per wheel
  int iterations = 0;
};
StaticState staticEquilibrium(const VehicleModel& model, RailSupport& rail, const std::vector<double>& x_m,
                              const std::vector<double>& unevenness_m);
/// The same on a rail given by its static compliance between the wheels' contact points (m/N; for
/// the full-width vehicle the points of each wheel's own rail).
StaticState staticEquilibrium(const VehicleModel& model, const Eigen::MatrixXd& rail_compliance_m_n,
                              const std::vector<double>& unevenness_m);

/// Per-sample outputs of a block; per-wheel arrays are sample-major: [k * wheels + i] (full width:
/// one wheel per rail per axle, VehicleModel::wheels()[i].rail).
struct PassageBlock {
  uint64_t first_index = 0;
  double time_step_s = 0.0;
  int wheel_count = 0;
  int body_count = 0;
  int sleeper_count = 0;
  /// Rail seats per sleeper in ballast_force_n: 1 (half track), 2 (full width: left, right).
  int rail_seat_count = 1;
  std::vector<double> time_s;
  std::vector<double> wheel_x_m;             ///< contact point position along the track
  std::vector<double> contact_force_n;       ///< compression positive
  std::vector<double> unevenness_m;          ///< height under the wheel (up)
  std::vector<double> rail_displacement_m;   ///< rail under the wheel (down)
  std::vector<double> wheel_displacement_m;  ///< contact DOF of the wheel (down)
  std::vector<BodyPose> poses;               ///< [k * body_count + b] when record_poses
  /// Ballast force on the foundation per rail seat (N, downward), when record_ballast:
  /// [(k * rail_seat_count + seat) * sleeper_count + s]; the half track has one seat: [k * sleeper_count + s].
  std::vector<double> ballast_force_n;
  size_t sampleCount() const { return time_s.size(); }
  void clear();
};

struct PassageOptions {
  bool record_poses = false;
  bool record_ballast = false;
};

class VehiclePassage {
 public:
  /// Throws ConfigError if dt is too coarse for the vehicle/defect, or the
  /// wheels leave the rail's usable range during `params.duration_s`.
  VehiclePassage(const VehicleModel& model, const Unevenness& unevenness, const PassageParams& params,
                 std::unique_ptr<RailSupport> rail, PassageOptions options = {});

  const VehicleModel& model() const { return model_; }
  const PassageParams& params() const { return params_; }
  RailSupport& rail() { return *rail_; }
  const StaticState& initialState() const { return static_; }

  /// Index of the next sample advance() produces (sample k at t = k dt).
  uint64_t nextSampleIndex() const { return emitted_; }
  /// Samples of the whole run: duration / dt + 1 (with sample 0).
  uint64_t totalSamples() const;
  bool finished() const { return emitted_ >= totalSamples(); }
  /// Produce up to n samples (fewer at the end of the run); appends to `out` after clear().
  size_t advance(size_t n, PassageBlock& out);

  // ---- current (last produced) state
  double time() const { return static_cast<double>(step_) * params_.time_step_s; }
  const std::vector<double>& contactForces() const { return F_; }
  const std::vector<double>& wheelPositions() const { return x_; }
  const std::vector<double>& unevennessUnderWheels() const { return z_; }
  const std::vector<double>& railDisplacementUnderWheels() const { return w_rail_; }
  std::vector<BodyPose> bodyPoses() const { return model_.poses(q_); }
  /// Front axle position at time t_s (wheels and body poses are offsets behind it).
  double frontAxlePosition(double t_s) const { return params_.front_axle_start_m + params_.speed_m_s * t_s; }
  /// Front axle position at the current time.
  double frontAxlePosition() const { return frontAxlePosition(time()); }
  const Eigen::VectorXd& displacement() const { return q_; }
  const Eigen::VectorXd& velocity() const { return v_; }
  /// Largest Newton iteration count so far.
  int maxNewtonIterations() const { return max_iter_; }

 private:
  void positionsAt(double t, std::vector<double>& x) const;
  void step();
  void record(PassageBlock& out);

  const VehicleModel& model_;
  const Unevenness& unevenness_;
  PassageParams params_;
  std::unique_ptr<RailSupport> rail_;
  PassageOptions options_;
  StaticState static_;
  int nw_;
  Eigen::MatrixXd Pq_, Pv_, Pa_, HB_, Gv_;
  Eigen::VectorXd hg_;
  Eigen::VectorXd q_, v_, a_, qs_, dfree_, wr_free_, Fv_;
  Eigen::MatrixXd Gr_, G_;
  std::vector<double> x_, z_, F_, w_rail_, radius_, scratch_;
  uint64_t step_ = 0, emitted_ = 0;
  int max_iter_ = 0;
  double tol_n_ = 1.0;
};

}  // namespace railvib::vehicle
