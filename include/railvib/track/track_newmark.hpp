// railvib/track: implicit Newmark (beta = 1/4, gamma = 1/2, constant dt) of
// a TrackModel, with a step API made for nonlinear wheel/rail coupling.
//
// The effective matrix K_eff = K + 4/dt^2 M + 2/dt C is factorised once
// (sparse Cholesky; the constructor throws std::runtime_error if K_eff is not
// positive definite). A step n -> n+1 under contact loads F_j at rail points
// p_j (positive downward) is linear in the loads:
//     u_{n+1} = u_free + sum_j F_j g_j,   g_j = K_eff^{-1} r_j,
// with u_free the end-of-step displacement without contact loads. Coupled use
// (the vehicle's Newton loop on the contact forces):
//
//   trk.predict();                           // or predict(other_force_next)
//   trk.setContactPoints(points);            // one back-substitution per point
//   // rail displacement at p_i: trk.contactFreeDisplacements()[i]
//   //   + sum_j trk.contactCompliance()(i, j) * F_j     (m, N, downward)
//   ... Newton on F ...
//   trk.commitContact(F);                    // no further solve
//
// Moving-load use: trk.step(loads). Each step costs one back-substitution; the
// unit responses come from cached columns of K_eff^{-1} at rail DOFs (one
// back-substitution the first time a node is touched), so the contact part
// costs 4 vector updates per point. The TrackModel must outlive the
// integrator. Not thread-safe (the column cache is mutable).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "railvib/track/track_model.hpp"

namespace railvib::track {

/// Sparse Cholesky backend for K_eff (both factorise once; see docs/track.md for timings).
enum class TrackSolverKind { EigenSimplicialLLT, CholmodSupernodalLLT };

class TrackNewmark {
 public:
  TrackNewmark(const TrackModel& model, double dt_s, TrackSolverKind solver = TrackSolverKind::EigenSimplicialLLT);
  ~TrackNewmark();
  TrackNewmark(const TrackNewmark&) = delete;
  TrackNewmark& operator=(const TrackNewmark&) = delete;

  const TrackModel& model() const { return model_; }
  double timeStep() const { return dt_; }
  /// Time of the current (committed) state and its step count.
  double time() const { return t_; }
  long stepCount() const { return steps_; }

  // ---- state
  const Eigen::VectorXd& displacement() const { return u_; }
  const Eigen::VectorXd& velocity() const { return v_; }
  const Eigen::VectorXd& acceleration() const { return a_; }
  /// Set an arbitrary state; acceleration from M a = f - C v - K u is NOT
  /// computed (M may be singular): pass it, or zero for a state at rest.
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t_s = 0.0);
  /// Static equilibrium under the loads, at rest (v = a = 0).
  void setStaticEquilibrium(const std::vector<PointLoad>& loads, double t_s = 0.0);
  /// Static deflection U under the loads, convected with them at speed V (steady moving-load
  /// start: u(x, t) = U(x - V t), so v = -V U' and a = V^2 U'' along the rail and the
  /// sleeper/foundation rows; derivatives by finite differences over the node positions).
  /// V = 0 is setStaticEquilibrium.
  void setConvectedStaticState(const std::vector<PointLoad>& loads, double speed_m_s, double t_s = 0.0);

  // ---- coupled step
  /// Free end-of-step displacement (no contact loads); optional extra nodal
  /// force vector at t_{n+1} (size dofCount()).
  void predict();
  void predict(const Eigen::VectorXd& other_external_force_next);
  const Eigen::VectorXd& freeDisplacement() const { return u_free_; }
  double freeDisplacementAt(const RailPoint& p) const { return p.displacement(u_free_); }
  /// out = K_eff^{-1} r_p: end-of-step displacements per unit load at p (m/N).
  /// Built from cached columns of K_eff^{-1} at rail DOFs (each column costs one
  /// back-substitution the first time a wheel reaches that node; K_eff is constant).
  void solveUnitLoad(const RailPoint& p, Eigen::VectorXd& out) const;
  /// r_i^T K_eff^{-1} r_j (m/N): end-of-step rail displacement at a per unit load at b.
  double compliance(const RailPoint& a, const RailPoint& b) const;
  /// Register this step's contact points: solves the unit responses and fills
  /// the compliance matrix and the free displacements at the points.
  void setContactPoints(const std::vector<RailPoint>& points);
  const std::vector<RailPoint>& contactPoints() const { return points_; }
  const Eigen::MatrixXd& contactCompliance() const { return G_; }
  const Eigen::VectorXd& contactFreeDisplacements() const { return w_free_; }
  /// Finish the step with forces at the registered contact points (N, downward).
  void commitContact(const std::vector<double>& forces_n);
  /// Finish the step with arbitrary point loads (one extra back-substitution).
  void commit(const std::vector<PointLoad>& contact_loads);

  // ---- plain step (moving loads): predict + commit
  void step(const std::vector<PointLoad>& loads);

  // ---- outputs
  double railDisplacement(double x_m) const;
  void ballastForces(std::vector<double>& out_half_track_n) const;
  /// Ballast force on the foundation under every rail seat (N, downward), seat-major:
  /// [seat * sleeperCount + sleeper], the left seats first; the half track has its one seat.
  void ballastForcesPerSeat(std::vector<double>& out_n) const;
  double kineticEnergy() const { return model_.kineticEnergy(v_); }
  double strainEnergy() const { return model_.strainEnergy(u_); }
  double totalEnergy() const { return kineticEnergy() + strainEnergy(); }

 private:
  void finish(const Eigen::VectorXd& u_next);
  void solveInPlace(Eigen::VectorXd& x) const;
  /// Column d of K_eff^{-1} (cached).
  const Eigen::VectorXd& inverseColumn(Eigen::Index d) const;

  struct Solver;
  const TrackModel& model_;
  double dt_;
  double a0_, a1_;
  std::unique_ptr<Solver> solver_;
  Eigen::VectorXd u_, v_, a_, u_free_, rhs_, tmp_, tmp2_;
  std::vector<RailPoint> points_;
  mutable std::vector<Eigen::VectorXd> columns_;
  mutable size_t cached_columns_ = 0;
  mutable std::vector<double> seat_scratch_;  // one seat's ballast forces (ballastForcesPerSeat)
  Eigen::MatrixXd G_;
  Eigen::VectorXd w_free_;
  bool predicted_ = false;
  double t_ = 0.0;
  long steps_ = 0;
};

}  // namespace railvib::track
