// railvib/soil (internal): the rigid body as a solver unit. RigidBodyCore holds the body and its
// reduced superstructure in double precision; RigidBodyUnit<Real> moves forces and motions between
// it and the solver's nodal fields.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "railvib/soil/mesh.hpp"
#include "railvib/soil/partition.hpp"
#include "railvib/soil/rigid_body.hpp"
#include "railvib/soil/soil_comm.hpp"
#include "railvib/soil/solver_unit.hpp"

namespace railvib::soil {

class RigidBodyCore {
 public:
  RigidBodyCore(const StructuredMesh& mesh, const std::vector<double>& mass, const RigidBodySpec& spec, double dt_s,
                double filter_decay, double beta_s);

  const std::vector<size_t>& nodes() const { return nodes_; }
  const std::vector<Eigen::Vector3d>& offsets() const { return offsets_; }
  /// Generalised soil force F_n = sum_a (f_a, r_a x f_a) for this step.
  void setForce(const Eigen::Matrix<double, 6, 1>& force);
  /// One central-difference step of the body and its modes.
  void advance();
  /// The step's matrices, for a unit that advances the body inside a larger implicit system
  /// (implicit_unit.hpp): coupled mass (carried soil nodes included; 6 rigid DOFs then the modes),
  /// damping (diagonal) and the DOFs not held.
  const Eigen::MatrixXd& coupledMass() const { return coupled_mass_; }
  const Eigen::VectorXd& dampingDiagonal() const { return damping_; }
  const std::vector<int>& activeDofs() const { return active_; }
  /// Velocities q'_{n-1/2} of all 6 + modes DOFs.
  const Eigen::VectorXd& fullVelocity() const { return v_; }
  /// The step's force F_n - K q_n of all DOFs: the soil's generalised force (setForce) on the rigid DOFs,
  /// the modes' -w^2 eta_n.
  const Eigen::VectorXd& stepForce();
  /// Take q'_{n+1/2} (all DOFs, held ones 0) solved elsewhere: q_{n+1}, the damping filter and the state.
  void commitVelocity(const Eigen::VectorXd& v_next);
  /// u + w x r_a of a rigid 6-vector at carried node a.
  Eigen::Vector3d nodeValue(const Eigen::Matrix<double, 6, 1>& q, size_t a) const;
  /// Adds the force f on carried node a to the generalised force g (F = f, M = r_a x f).
  void addNodeForce(size_t a, const Eigen::Vector3d& f, Eigen::Matrix<double, 6, 1>& g) const {
    g.head<3>() += f;
    g.tail<3>() += offsets_[a].cross(f);
  }
  /// The soil fields the body gives carried node a after its step: u, v and w = u + beta vf.
  struct NodeFields {
    Eigen::Vector3d u, v, w;
  };
  NodeFields nodeFields(size_t a) const;
  double energy() const;
  const RigidBodyState& state() const { return state_; }
  const RigidBodySpec& spec() const { return spec_; }

 private:
  RigidBodySpec spec_;
  double dt_, e_, beta_;
  std::vector<size_t> nodes_;
  std::vector<Eigen::Vector3d> offsets_;
  std::vector<int> active_;  // DOFs not held
  Eigen::MatrixXd a_inv_, a_inv_b_;
  Eigen::MatrixXd extra_mass_;    // coupled mass matrix minus the carried soil nodes' part
  Eigen::MatrixXd coupled_mass_;  // the whole coupled mass matrix
  Eigen::VectorXd damping_;       // modal damping 2 z w (0 for the rigid DOFs)
  Eigen::VectorXd omega2_;        // modal stiffness (0 for the rigid DOFs)
  Eigen::VectorXd x_, v_, vf_, force_;
  Eigen::Matrix<double, 6, 1> soil_force_ = Eigen::Matrix<double, 6, 1>::Zero();
  RigidBodyState state_;
};

template <class Real>
class RigidBodyUnit final : public SolverUnit<Real> {
 public:
  RigidBodyUnit(const StructuredMesh& mesh, const std::vector<double>& mass, const RigidBodySpec& spec, double dt_s,
                double filter_decay, double beta_s)
      : core_(mesh, mass, spec, dt_s, filter_decay, beta_s), local_(core_.nodes()), owned_(core_.nodes().size(), 1) {}

  /// Spread over ranks (the core was built on the whole mesh, identically on every rank): this rank
  /// gathers the forces of the carried nodes it owns, the generalised force is summed over the ranks in
  /// rank order (the same sum on every rank), and the rank writes the motion of the nodes in its slab.
  void spread(const StructuredMesh& global_mesh, const StructuredMesh& slab, const SlabPartition& partition,
              SoilComm* comm) {
    comm_ = comm;
    mapToSlab(core_.nodes(), global_mesh, slab, partition, local_, owned_);
  }

  void readForces(const StepContext<Real>& ctx) override {
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    for (size_t a = 0; a < local_.size(); ++a) {
      if (!owned_[a]) continue;
      const size_t n = local_[a];
      const Eigen::Vector3d f(static_cast<double>(ctx.fields.f[0][n]), static_cast<double>(ctx.fields.f[1][n]),
                              static_cast<double>(ctx.fields.f[2][n]));
      core_.addNodeForce(a, f, g);
    }
    if (comm_) comm_->sumInRankOrder(g.data(), 6, gathered_);
    core_.setForce(g);
  }

  void afterUpdate(StepContext<Real>& ctx) override {
    core_.advance();
    for (size_t a = 0; a < local_.size(); ++a) {
      const size_t n = local_[a];
      if (n == kNotInSlab) continue;
      const RigidBodyCore::NodeFields q = core_.nodeFields(a);
      for (int c = 0; c < 3; ++c) {
        ctx.fields.u[c][n] = static_cast<Real>(q.u[c]);
        ctx.fields.v[c][n] = static_cast<Real>(q.v[c]);
        ctx.fields.w[c][n] = static_cast<Real>(q.w[c]);
      }
    }
  }

  double energy(const StepContext<Real>& /*ctx*/) const override { return core_.energy(); }
  const RigidBodyCore& core() const { return core_; }

 private:
  RigidBodyCore core_;
  std::vector<size_t> local_;  // per carried node: its index in this rank's slab, or kNotInSlab
  std::vector<char> owned_;    // per carried node: this rank gathers its force
  SoilComm* comm_ = nullptr;
  std::vector<double> gathered_;
};

}  // namespace railvib::soil
