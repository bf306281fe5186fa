// railvib/soil: the seams of the explicit soil solver.
//
// One step of Solver (central difference, velocity form; see solver.hpp):
//   1. the stiffness kernel adds f -= K w over its element box (kernel.hpp);
//   2. every unit's addForces() adds what the kernel does not compute (e.g. a
//      PML integrates the elements of its layer itself);
//   3. the external loads (force channels) are added;
//   4. every unit's readForces() sees the complete nodal forces f_n (e.g. a
//      rigid foundation gathers the forces on the soil nodes it carries);
//   5. the nodal update of every node: v, u, the damping filter vf and
//      w = u + beta vf, with the diagonal damping of the boundary (dashpots,
//      graded layer) treated semi-implicitly; f is cleared;
//   6. every unit's afterUpdate() may overwrite the nodes it owns (a PML's
//      split-field nodes, the nodes slaved to a rigid foundation).
// A unit never touches the kernel and the kernel knows no unit: a new boundary
// or attached structure plugs in here.
#pragma once

#include <cstddef>
#include <vector>

#include "railvib/soil/mesh.hpp"

namespace railvib::soil {

/// The solver's nodal fields (structure of arrays, one array per component 0 x,
/// 1 y, 2 d = down; node index of StructuredMesh::node()).
template <class Real>
struct NodalFields {
  size_t node_count = 0;
  Real* u[3] = {nullptr, nullptr, nullptr};  // displacement u_n (u_{n+1} after the update)
  Real* v[3] = {nullptr, nullptr, nullptr};  // half-step velocity v_{n-1/2} (v_{n+1/2} after)
  // w = u + beta vf, the field the stiffness acts on; it also holds the state of the Rayleigh damping
  // filter (the low-passed velocity vf = (w - u) / beta): a unit that sets u sets w with it.
  Real* w[3] = {nullptr, nullptr, nullptr};
  Real* f[3] = {nullptr, nullptr, nullptr};  // nodal force f_n being accumulated (N)
  /// Update coefficients v_{n+1/2} = va v_{n-1/2} + vb f_n (both 0 for a constrained component).
  const Real* va[3] = {nullptr, nullptr, nullptr};
  const Real* vb[3] = {nullptr, nullptr, nullptr};
  bool fixed(size_t node, int c) const { return va[c][node] == Real(0) && vb[c][node] == Real(0); }
};

/// What a unit sees of the solver during a step.
template <class Real>
struct StepContext {
  const StructuredMesh* mesh = nullptr;
  NodalFields<Real> fields;
  const std::vector<double>* mass = nullptr;  // lumped nodal mass (kg)
  Real dt = 0;                                // step (s)
  Real beta = 0;                              // stiffness-proportional Rayleigh coefficient (s)
  Real filter_decay = 0;                      // e = exp(-omega_c dt) of the damping filter
  int threads = 1;
  unsigned long long step = 0;  // index n of the step being taken (t_n = n dt)
};

/// Runtime part of a boundary or an attached structure, for one precision.
template <class Real>
class SolverUnit {
 public:
  virtual ~SolverUnit() = default;
  /// Step 2: element contributions the kernel does not make (f -= ...).
  virtual void addForces(StepContext<Real>& /*ctx*/) {}
  /// Step 4: the nodal forces f_n are complete (kernel, units, loads).
  virtual void readForces(const StepContext<Real>& /*ctx*/) {}
  /// Step 6: after the nodal update, overwrite the nodes this unit owns.
  virtual void afterUpdate(StepContext<Real>& /*ctx*/) {}
  /// Energy the unit holds outside the nodal fields (e.g. a structure's own DOFs), J; for energy checks.
  virtual double energy(const StepContext<Real>& /*ctx*/) const { return 0.0; }
};

}  // namespace railvib::soil
