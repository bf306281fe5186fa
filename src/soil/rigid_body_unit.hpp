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
  /// damping (diagonal), stiffness (diagonal: the modes' w^2) and the DOFs not held.
  const Eigen::MatrixXd& coupledMass() const { return coupled_mass_; }
  const Eigen::VectorXd& dampingDiagonal() const { return damping_; }
  const Eigen::VectorXd& stiffnessDiagonal() const { return omega2_; }
  const std::vector<int>& activeDofs() const { return active_; }
  /// Velocities q'_{n-1/2} and displacements q_n of all 6 + modes DOFs, and the generalised force F_n.
  const Eigen::VectorXd& fullVelocity() const { return v_; }
  const Eigen::VectorXd& fullDisplacement() const { return x_; }
  const Eigen::Matrix<double, 6, 1>& soilForce() const { return soil_force_; }
  /// Take q'_{n+1/2} (all DOFs, held ones 0) solved elsewhere: q_{n+1}, the damping filter and the state.
  void commitVelocity(const Eigen::VectorXd& v_next);
  /// u + w x r_a of a rigid 6-vector at carried node a.
  Eigen::Vector3d nodeValue(const Eigen::Matrix<double, 6, 1>& q, size_t a) const;
  Eigen::Matrix<double, 6, 1> displacement() const { return x_.head<6>(); }
  Eigen::Matrix<double, 6, 1> velocity() const { return v_.head<6>(); }
  Eigen::Matrix<double, 6, 1> filteredVelocity() const { return vf_; }
  double beta() const { return beta_; }
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
      : core_(mesh, mass, spec, dt_s, filter_decay, beta_s),
        local_(core_.nodes()),
        owned_(core_.nodes().size(), 1),
        global_sx_(mesh.nx + 1),
        global_sxy_((mesh.nx + 1) * (mesh.ny + 1)) {}

  /// Spread over ranks (the core was built on the whole mesh, identically on every rank): this rank
  /// gathers the forces of the carried nodes it owns, the generalised force is summed over the ranks in
  /// rank order (the same sum on every rank), and the rank writes the motion of the nodes in its slab.
  void spread(const StructuredMesh& slab, const SlabPartition& partition, SoilComm* comm) {
    comm_ = comm;
    for (size_t a = 0; a < core_.nodes().size(); ++a) {
      const size_t g = core_.nodes()[a];
      const size_t i = g % global_sx_, j = (g % global_sxy_) / global_sx_, k = g / global_sxy_;
      owned_[a] = partition.ownsNodePlane(i) ? 1 : 0;
      local_[a] = partition.holdsNodePlane(i) ? slab.node(i - partition.begin(), j, k) : kNone;
    }
  }

  void readForces(const StepContext<Real>& ctx) override {
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    for (size_t a = 0; a < local_.size(); ++a) {
      if (!owned_[a]) continue;
      const size_t n = local_[a];
      const Eigen::Vector3d f(static_cast<double>(ctx.fields.f[0][n]), static_cast<double>(ctx.fields.f[1][n]),
                              static_cast<double>(ctx.fields.f[2][n]));
      g.head<3>() += f;
      g.tail<3>() += core_.offsets()[a].cross(f);
    }
    if (comm_) {
      comm_->allGather(g.data(), 6, gathered_);
      g.setZero();
      for (size_t r = 0; r < gathered_.size() / 6; ++r)
        g += Eigen::Map<const Eigen::Matrix<double, 6, 1>>(&gathered_[6 * r]);
    }
    core_.setForce(g);
  }

  void afterUpdate(StepContext<Real>& ctx) override {
    core_.advance();
    const Eigen::Matrix<double, 6, 1> u = core_.displacement(), v = core_.velocity(), vf = core_.filteredVelocity();
    for (size_t a = 0; a < local_.size(); ++a) {
      const size_t n = local_[a];
      if (n == kNone) continue;
      const Eigen::Vector3d ua = core_.nodeValue(u, a), va = core_.nodeValue(v, a), vfa = core_.nodeValue(vf, a);
      for (int c = 0; c < 3; ++c) {
        ctx.fields.u[c][n] = static_cast<Real>(ua[c]);
        ctx.fields.v[c][n] = static_cast<Real>(va[c]);
        ctx.fields.w[c][n] = static_cast<Real>(ua[c] + core_.beta() * vfa[c]);
      }
    }
  }

  double energy(const StepContext<Real>& /*ctx*/) const override { return core_.energy(); }
  const RigidBodyCore& core() const { return core_; }

 private:
  static constexpr size_t kNone = static_cast<size_t>(-1);
  RigidBodyCore core_;
  std::vector<size_t> local_;  // per carried node: its index in this rank's slab, or kNone
  std::vector<char> owned_;    // per carried node: this rank gathers its force
  size_t global_sx_, global_sxy_;
  SoilComm* comm_ = nullptr;
  std::vector<double> gathered_;
};

}  // namespace railvib::soil
