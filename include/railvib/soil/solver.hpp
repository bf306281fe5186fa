// railvib/soil: matrix-free explicit elastodynamics on a StructuredMesh.
//
// Scheme (lumped mass M, central difference in velocity form, internal frame
// x, y, d = depth down):
//   w_n       = u_n + beta * vf_n                    (damped "effective" field)
//   f_n       = f_ext(t_n) - K w_n                   (matrix-free stiffness kernel, kernel.hpp)
//   v_{n+1/2} = ((M/dt - C/2) v_{n-1/2} + f_n) / (M/dt + C/2)   (C diagonal)
//   u_{n+1}   = u_n + dt v_{n+1/2}
//   vf_{n+1}  = e vf_n + (1 - e) v_{n+1/2},  e = exp(-omega_c dt)
// (vf has no array of its own: beta vf_n = w_n - u_n, and w_{n+1} carries vf_{n+1}.)
// C is the diagonal damping of the boundary (Lysmer-Kuhlemeyer dashpots, a
// graded mass-proportional layer; boundary.hpp); it is treated semi-
// implicitly (no step limit). Boundaries that need more (a PML) and structures
// attached to the soil plug in as units (solver_unit.hpp). The stiffness-
// proportional Rayleigh damping beta K v is applied to a one-pole low-passed
// velocity vf (cut-off omega_c above the band of interest): the damping ratio
// is beta omega / 2 / (1 + (omega/omega_c)^2) in the band, and above omega_c
// the damping fades out and the operator tends to (1 + beta omega_c) K, so the
// stable step is the undamped one divided by sqrt(1 + beta omega_c) instead of
// being multiplied by sqrt(1 + xi^2) - xi with xi = beta omega_max / 2.
// See docs/soil.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "railvib/soil/boundary.hpp"
#include "railvib/soil/kernel.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/partition.hpp"
#include "railvib/soil/rigid_body.hpp"
#include "railvib/soil/soil_comm.hpp"

namespace railvib::soil {

enum class Precision { Float, Double };

struct SolverExtra;

struct SolverOptions {
  /// Faces that absorb (the others reflect, e.g. symmetry planes); the top is the free surface.
  AbsorbingFaces absorbing;
  /// Non-reflecting boundary on the absorbing faces (boundary.hpp).
  BoundarySpec boundary;
  /// Stiffness kernel (kernel.hpp).
  KernelKind kernel = KernelKind::Element;
  /// Constrain u_x = u_y = 0 everywhere (1D column tests).
  bool lateral_rollers = false;
  /// Symmetry planes (u_x = 0 on x = x_min, u_y = 0 on y = y_min), e.g. quarter models.
  bool symmetry_x_min = false, symmetry_y_min = false;
  /// Antisymmetry planes (the in-plane components vanish: u_y = u_d = 0 on x = x_min, u_x = u_d = 0 on
  /// y = y_min), e.g. a footing rocking about an axis lying in the plane.
  bool antisymmetry_x_min = false, antisymmetry_y_min = false;
  /// Fix every bottom node (static tests; instead of the bottom dashpots).
  bool fixed_bottom = false;
  /// Uniform mass-proportional damping alpha M v (1/s) (dynamic relaxation in static tests).
  double mass_damping_1_s = 0.0;
  /// Stiffness-proportional Rayleigh coefficient and cut-off of the damping filter.
  double rayleigh_beta_s = 0.0;
  double damping_cutoff_hz = 300.0;
  /// Fraction of the stability limit used.
  double safety_factor = 0.9;
  /// If > 0: dt is lowered so that 1/dt is an integer multiple of this rate.
  double align_rate_hz = 0.0;
  /// Explicit step (0 = computed). Refused if above the stability limit.
  double dt_s = 0.0;
  Precision precision = Precision::Float;
  /// OpenMP threads (0 = all).
  int threads = 0;
  /// MPI ranks the soil expects (0 = as many as the launcher started; else they must agree).
  int ranks = 0;
};

/// Bytes of state the solver allocates for a mesh (checked before allocation).
size_t solverMemoryBytes(const StructuredMesh& mesh, Precision precision);

/// The mesh's inclusions must lie off the absorbing faces and outside the boundary's zone (its
/// dashpots and layers are set from the level materials). Throws std::invalid_argument naming the
/// first that does not, with the room there is.
void checkInclusionsInside(const StructuredMesh& mesh, const AbsorbingFaces& faces, const SoilBoundary& boundary);

/// A sparse set of nodal force weights driven by one scalar channel:
/// f[node][component] += weight * value(channel).
struct ForceChannel {
  std::vector<size_t> nodes;
  std::vector<int> components;  // 0 x, 1 y, 2 d (down)
  std::vector<double> weights;
};

/// Spread over ranks (a communicator of more than one rank), every rank constructs the Solver with
/// the same global mesh and options and calls step() in lockstep; each integrates its slab of element
/// columns (partition.hpp) and exchanges the forces of the shared node planes with its neighbours,
/// sent before and received after the slab's interior elements are integrated. Node indices and
/// coordinates at the interface are global; a node accessor refuses a node outside this rank's slab.
class Solver {
 public:
  Solver(StructuredMesh mesh, const SolverOptions& options, std::shared_ptr<SoilComm> comm = nullptr);
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  /// The whole mesh (on every rank).
  const StructuredMesh& mesh() const { return global_mesh_; }
  /// This rank's slab as a mesh of its own (the whole mesh on one rank).
  const StructuredMesh& localMesh() const { return mesh_; }
  const SlabPartition& partition() const { return partition_; }
  SoilComm& comm() const { return *comm_; }
  /// Index in localMesh() of a global node, or npos when it is not in this rank's slab.
  size_t localNode(size_t global_node) const;
  /// Whether this rank owns the point (x, y) for outputs (the element column holding x is in its slab).
  bool ownsPoint(double x_m) const;
  /// Whether this rank owns global node plane i (outputs, point loads).
  bool ownsNodePlane(size_t i) const { return partition_.ownsNodePlane(i); }
  const SolverOptions& options() const { return options_; }
  double dt() const { return dt_; }
  /// Undamped stability limit 2 / sqrt(lambda_max) (element bound) and the
  /// limit with the filtered Rayleigh damping (before the safety factor).
  double dtUndamped() const { return dt_undamped_; }
  double dtDamped() const { return dt_damped_; }
  /// The limit a naive explicit beta K v would impose.
  double dtNaiveRayleigh() const { return dt_naive_; }
  uint64_t stepCount() const { return steps_; }
  double time() const { return dt_ * static_cast<double>(steps_); }
  size_t memoryBytes() const;

  /// Attach a rigid body carried by the soil nodes of its region, with its reduced superstructure
  /// (rigid_body.hpp), before the first step; returns its index. Throws std::invalid_argument.
  size_t attachRigidBody(const RigidBodySpec& spec);
  size_t rigidBodyCount() const;
  /// State after the last step.
  const RigidBodyState& rigidBody(size_t index) const;
  /// Energy the units hold outside the nodal fields (a superstructure's own DOFs), J.
  double unitEnergy() const;
  /// The implicit inclusions' solve once factorised (at the first step; all 0 before, or without implicit
  /// inclusions): its unknowns, the entries of its factor, the sizes of its two parts and separator.
  struct ImplicitSolveInfo {
    size_t unknowns = 0;
    long factor_nonzeros = 0, part_0 = 0, part_1 = 0, separator = 0;
  };
  ImplicitSolveInfo implicitSolve() const;

  /// Register a load channel (global nodes; a rank keeps the nodes it owns); returns its index.
  size_t addForceChannel(ForceChannel channel);
  /// Values of all channels for the next step (size = channel count).
  void setChannelValues(const std::vector<double>& values);
  /// Advance one step with the current channel values at t_n.
  void step();
  /// Advance n steps (channel values held).
  void run(uint64_t n);

  /// Displacement / velocity (v at t_{n-1/2}) component c of a node, internal frame.
  double displacement(size_t node, int c) const;
  double velocity(size_t node, int c) const;
  /// Set displacement (tests: initial conditions). Velocity and filter state remain.
  void setDisplacement(size_t node, int c, double value);
  void setVelocity(size_t node, int c, double value);
  /// Trilinear interpolation of the half-step velocity at a point (x, y, depth).
  void velocityAt(double x, double y, double d, double out[3]) const;
  void displacementAt(double x, double y, double d, double out[3]) const;
  /// Half-step velocity component (0 x, 1 y, 2 z down; internal frame) of every surface node of the
  /// whole mesh, (nx+1)(ny+1) values, i fastest; 0 at the nodes this rank does not own (a sum over
  /// the ranks gives the field).
  void surfaceVelocity(int component, std::vector<double>& out) const;

  /// Internal force -K u of the kernel's elements for the current displacement (tests: equilibrium, eigen).
  void internalForce(std::vector<double>& f_out) const;
  /// Lumped nodal mass.
  double nodalMass(size_t node) const;
  /// Kinetic energy with the half-step velocity of the nodes this rank owns (the whole mesh on one rank).
  double kineticEnergy() const;

  /// The boundary and the stiffness kernel in use.
  const SoilBoundary& boundary() const { return *boundary_; }
  KernelKind kernel() const { return options_.kernel; }
  /// Elements the stiffness kernel integrates (the boundary integrates the others).
  const ElementBox& kernelElements() const { return kernel_box_; }
  /// Multiply-adds of the stiffness kernel per step.
  double kernelMultiplyAddsPerStep() const;

  struct Impl;

 private:
  void computeStabilityLimits();
  void chooseStep();
  std::array<std::vector<double>, 3> diagonalDamping() const;
  void sumSharedPlanes(std::vector<double>& values) const;

  std::unique_ptr<SolverExtra> extra_;
  StructuredMesh global_mesh_;
  StructuredMesh mesh_;  // this rank's slab
  SolverOptions options_;
  std::shared_ptr<SoilComm> comm_;
  SlabPartition partition_;
  std::unique_ptr<SoilBoundary> boundary_;
  ElementBox kernel_box_;
  double dt_ = 0.0, dt_undamped_ = 0.0, dt_damped_ = 0.0, dt_naive_ = 0.0;
  uint64_t steps_ = 0;
  std::unique_ptr<Impl> impl_;
};

}  // namespace railvib::soil
