// railvib/soil (internal): material inclusions integrated implicitly, as a solver unit.
//
// A stiff inclusion in a soft soil (a concrete foundation: P waves ~3000 m/s against the soil's
// ~200-1400 m/s) would set the explicit step of the whole mesh. Its elements' stiffness K_I is instead
// taken implicitly and the soil's K_E explicitly, the implicit-explicit element partition of Hughes &
// Liu (J. Appl. Mech. 45, 1978):
//   (M + dt^2/4 K_I) (u_{n+1} - 2 u_n + u_{n-1}) / dt^2 + (K_E + K_I) u_n = f_n
// the average-acceleration Newmark rule on K_I and the central difference on K_E. Written with
// M' = M - dt^2/4 K_E it is the average-acceleration rule on (M', K_E + K_I), which conserves its energy
// while M' stays positive definite: the step limit is the explicit elements' alone, and the inclusion's
// own modes below ~1/(10 dt) are integrated to O(dt^2) as by the soil's central difference.
// The kernel and the other units compute f_n - K u_n as always; this unit replaces the diagonal
// update of the inclusions' nodes by one solve per step, in the solver's velocity form with its
// diagonal damping C (NodalFields::va, vb):
//   (M/dt + C/2 + dt/4 K_I) v_{n+1/2} = (M/dt - C/2 + dt/4 K_I) v_{n-1/2} + f_n
// An inclusion's own Rayleigh damping beta K_I joins C, integrated by the same trapezoidal rule (it
// would set the step again if explicit); it damps the inclusion's stiff modes, which the
// average-acceleration rule alone carries undamped.
// The matrix is constant: assembled and factorised (sparse LDL^T, split_ldlt.hpp: its substitutions on
// two threads) once, at the first step, when the nodal coefficients are known on every rank. A rigid body
// (rigid_body.hpp) joins the same solve (a house standing on a meshed foundation): its carried nodes follow u_a = R_a
// q, so its rows and columns are R^T (...) R plus its coupled mass and modal damping, and its generalised force is
// sum_a R_a^T f_a. The unit keeps its nodes' state (u, v, the damping filter) itself and writes it
// into the nodal fields after every step (InclusionUnit takes the soil's own damping off the inclusion).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"
#include "railvib/soil/partition.hpp"
#include "railvib/soil/soil_comm.hpp"
#include "railvib/soil/solver_unit.hpp"
#include "rigid_body_unit.hpp"
#include "split_ldlt.hpp"

namespace railvib::soil {

/// The implicit inclusions' nodes and the bodies in one constant linear system (double precision,
/// identical on every rank).
class ImplicitCore {
 public:
  /// `mesh`: the whole mesh (its inclusions flagged implicit are taken); dt and the damping filter as
  /// the solver's; `threads` >= 2 substitutes on two threads (split_ldlt.hpp).
  ImplicitCore(const StructuredMesh& mesh, double dt_s, double filter_decay, double beta_s, int threads);

  /// A rigid body advanced inside this system instead of by its own unit (before the first step).
  void absorb(std::unique_ptr<RigidBodyCore> body);
  const std::vector<std::unique_ptr<RigidBodyCore>>& bodies() const { return bodies_; }

  /// Nodes whose values the solve needs and writes: the inclusions' nodes, then the bodies' carried
  /// nodes not already listed (global node indices).
  const std::vector<size_t>& nodes() const { return nodes_; }
  const StructuredMesh& mesh() const { return mesh_; }
  size_t implicitNodeCount() const { return implicit_nodes_; }
  size_t unknowns() const { return static_cast<size_t>(rhs_.size()); }
  const SplitLdlt& factor() const { return solver_; }
  bool ready() const { return ready_; }

  /// First step: per node (order of nodes()) va, vb, u, v and beta vf (3 each, 15 values) as the
  /// solver had them; assembles and factorises.
  void initialise(const std::vector<double>& node_values);
  /// One step: f_n per node (3 each) in, the new u, v and w = u + beta vf per node out (9 each).
  void advance(const std::vector<double>& force, std::vector<double>& out);
  /// Energy outside the nodal fields (the bodies' superstructures), J.
  double energy() const;

 private:
  struct Element {
    size_t node[8];
    const double* stiffness;  // 24 x 24, row-major, DOF 3 c + d for corner c, component d
    double beta_s = 0.0;      // its inclusion's Rayleigh coefficient
  };
  struct Carried {
    int body = -1;
    size_t index = 0;  // in the body's carried nodes
  };
  // A nodal displacement component as a combination of unknowns.
  struct Term {
    int unknown;
    double coefficient;
  };
  void terms(size_t node, int component, std::vector<Term>& out) const;

  const StructuredMesh& mesh_;
  double dt_, e_, beta_;
  std::vector<std::vector<double>> level_stiffness_;  // per inclusion, per level k: 576 values
  std::vector<Element> elements_;
  std::vector<size_t> nodes_;
  size_t implicit_nodes_ = 0;
  std::vector<Carried> carried_;  // per node in nodes_
  std::vector<std::unique_ptr<RigidBodyCore>> bodies_;
  std::vector<int> dof_;              // per node and component: unknown or -1 (fixed or carried)
  std::vector<int> body_offset_;      // first unknown of each body's active DOFs
  std::vector<double> u_, filtered_;  // per node and component: u_n, beta vf_n
  SplitLdlt solver_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> stiffness_damping_;  // beta K_I over the unknowns
  int threads_ = 1;
  Eigen::VectorXd damping_, z_, rhs_;
  // Per step, kept to avoid allocations: the bodies' generalised soil forces and a body's new velocity.
  std::vector<Eigen::Matrix<double, 6, 1>> generalised_;
  Eigen::VectorXd body_velocity_;
  bool ready_ = false;
};

template <class Real>
class ImplicitUnit final : public SolverUnit<Real> {
 public:
  ImplicitUnit(const StructuredMesh& global_mesh, double dt_s, double filter_decay, double beta_s, int threads)
      : core_(global_mesh, dt_s, filter_decay, beta_s, threads) {
    mapNodes(nullptr, nullptr);
  }

  void absorb(std::unique_ptr<RigidBodyCore> body) {
    core_.absorb(std::move(body));
    mapNodes(slab_, partition_);
  }

  /// Spread over ranks: the core is built on the whole mesh on every rank; each rank contributes the
  /// values of the nodes it owns and writes those its slab holds.
  void spread(const StructuredMesh& slab, const SlabPartition& partition, SoilComm* comm) {
    comm_ = comm;
    slab_ = &slab;
    partition_ = &partition;
    mapNodes(slab_, partition_);
  }

  void readForces(const StepContext<Real>& ctx) override {
    const size_t n = core_.nodes().size();
    if (!core_.ready()) {
      std::vector<double> values(15 * n, 0.0);
      for (size_t a = 0; a < n; ++a) {
        if (!owned_[a]) continue;
        const size_t nd = local_[a];
        for (int c = 0; c < 3; ++c) {
          values[15 * a + c] = static_cast<double>(ctx.fields.va[c][nd]);
          values[15 * a + 3 + c] = static_cast<double>(ctx.fields.vb[c][nd]);
          values[15 * a + 6 + c] = static_cast<double>(ctx.fields.u[c][nd]);
          values[15 * a + 9 + c] = static_cast<double>(ctx.fields.v[c][nd]);
          values[15 * a + 12 + c] = static_cast<double>(ctx.fields.w[c][nd] - ctx.fields.u[c][nd]);
        }
      }
      sumOverRanks(values);
      core_.initialise(values);
    }
    force_.assign(3 * n, 0.0);
    for (size_t a = 0; a < n; ++a) {
      if (!owned_[a]) continue;
      for (int c = 0; c < 3; ++c) force_[3 * a + c] = static_cast<double>(ctx.fields.f[c][local_[a]]);
    }
    sumOverRanks(force_);
  }

  void afterUpdate(StepContext<Real>& ctx) override {
    core_.advance(force_, out_);
    for (size_t a = 0; a < local_.size(); ++a) {
      const size_t nd = local_[a];
      if (nd == kNotInSlab) continue;
      for (int c = 0; c < 3; ++c) {
        ctx.fields.u[c][nd] = static_cast<Real>(out_[9 * a + c]);
        ctx.fields.v[c][nd] = static_cast<Real>(out_[9 * a + 3 + c]);
        ctx.fields.w[c][nd] = static_cast<Real>(out_[9 * a + 6 + c]);
      }
    }
  }

  double energy(const StepContext<Real>& /*ctx*/) const override { return core_.energy(); }
  const ImplicitCore& core() const { return core_; }

 private:
  // Serial: every node is this rank's. Spread: where each is in the slab (soil/partition.hpp).
  void mapNodes(const StructuredMesh* slab, const SlabPartition* partition) {
    const std::vector<size_t>& nodes = core_.nodes();
    if (!partition) {
      local_ = nodes;
      owned_.assign(nodes.size(), 1);
      return;
    }
    mapToSlab(nodes, core_.mesh(), *slab, *partition, local_, owned_);
  }

  // Each node's values come from its owner (the others contribute 0): the sum over ranks.
  void sumOverRanks(std::vector<double>& values) {
    if (comm_) comm_->sumInRankOrder(values.data(), values.size(), gathered_);
  }

  ImplicitCore core_;
  const StructuredMesh* slab_ = nullptr;
  const SlabPartition* partition_ = nullptr;
  SoilComm* comm_ = nullptr;
  std::vector<size_t> local_;
  std::vector<char> owned_;
  std::vector<double> force_, out_, gathered_;
};

}  // namespace railvib::soil
