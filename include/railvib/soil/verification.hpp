// railvib/soil: verification problems shared by the unit tests and
// `railvib_tool soil-bench` (column, damping decay, throughput, Lamb).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "railvib/soil/kernel.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/soil_comm.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

/// 1D column (1 x 1 elements in plane, lateral rollers, Lysmer base) under a
/// top pressure q: either a smoothed step (velocity vs q / (rho Vp)) or a
/// smooth pulse (reflection at the absorbing base).
struct ColumnSpec {
  Material material{61.0e6, 1876.0, 0.13};
  double length_m = 20.0;
  double dz_m = 0.1;
  double pressure_pa = 1.0e4;
  /// Rise time of the step / duration of the Hann pulse.
  double rise_s = 0.01;
  double receiver_depth_m = 10.0;
  Precision precision = Precision::Float;
  KernelKind kernel = KernelKind::Element;
};

struct ColumnResult {
  double expected_velocity_m_s = 0.0;     // q / (rho Vp)
  double incident_velocity_m_s = 0.0;     // step plateau before the base reflection comes back
  double after_velocity_m_s = 0.0;        // plateau after the base reflection passed the receiver
  double velocity_error = 0.0;            // incident / expected - 1
  double step_reflection = 0.0;           // (after - incident) / incident
  double pulse_incident_peak_m_s = 0.0;   // Hann pulse: incident peak
  double pulse_reflected_peak_m_s = 0.0;  // largest |v| in the window of the reflected pulse
  double pulse_reflection = 0.0;          // reflected / incident
  double dt_s = 0.0;
  size_t elements = 0;
};

ColumnResult runColumn(const ColumnSpec& spec);

/// Decay of one free elastic mode of a small free box (2 x 2 x 2 elements),
/// scaled so that the mode is at f_hz, with Rayleigh beta and the damping
/// filter cut-off; measured from the modal amplitude envelope.
struct DampingDecayResult {
  double frequency_hz = 0.0;    // measured mode frequency
  double measured_ratio = 0.0;  // decay rate / omega
  double target_ratio = 0.0;    // beta omega / 2
  double dt_s = 0.0, dt_undamped_s = 0.0, dt_naive_s = 0.0;
};
DampingDecayResult runDampingDecay(double f_hz, double beta_s, double cutoff_hz, Precision precision);

/// Side-by-side timing of stiffness kernels on one homogeneous box with Lysmer faces and Rayleigh damping:
/// for every repeat each kernel in turn runs `steps` solver steps, then `steps` applications of the kernel
/// alone (same mesh and box), so that the kernels see the same machine load.
struct ThroughputSpec {
  size_t nx = 160, ny = 80, nz = 30;
  int threads = 1;
  Precision precision = Precision::Float;
  int steps = 20;
  int repeat = 5;
  std::vector<KernelKind> kernels{KernelKind::Element, KernelKind::Stencil};
  BoundarySpec boundary;  // on the five absorbing faces (default: Lysmer dashpots)
};

/// One kernel's figures: medians over the repeats.
struct ThroughputResult {
  KernelKind kernel = KernelKind::Element;
  size_t elements = 0;
  size_t boundary_elements = 0;  // integrated by the boundary's unit (a PML), not the kernel
  int threads = 0;
  double element_updates_per_s = 0.0;      // whole solver steps, wall clock
  double element_updates_per_cpu_s = 0.0;  // per CPU second of the process (user + sys, all threads)
  double min_element_updates_per_s = 0.0, max_element_updates_per_s = 0.0;
  double seconds_per_step = 0.0;          // whole solver step (kernel + nodal update)
  double kernel_seconds_per_apply = 0.0;  // the kernel alone
  double cpu_seconds_per_step = 0.0;      // CPU time (all threads) of a whole step
  double kernel_cpu_seconds_per_apply = 0.0;
  double kernel_element_updates_per_s = 0.0;
  double multiply_adds_per_step = 0.0;  // StiffnessKernel::multiplyAddsPerApply
  double kernel_gflop_s = 0.0;          // 2 flops per multiply-add, kernel alone
  /// Step rate / the first kernel's, median of the ratios of the same repeat.
  double step_ratio_to_first = 1.0;
  double kernel_ratio_to_first = 1.0;
};
std::vector<ThroughputResult> runThroughput(const ThroughputSpec& spec);

/// Strong scaling over MPI ranks (docs/soil.md, "MPI ranks"), run by every rank of `comm`: each repeat
/// first times `steps` steps of the whole mesh on rank 0 alone (one rank, no MPI; the others sleep in a
/// quiet barrier), then `steps` steps of the mesh spread over all ranks. A point load drives the surface
/// so that the fields are not zero. Figures of the spread run are rank 0's wall clock between barriers.
struct RankScalingSpec {
  StructuredMesh mesh;
  SolverOptions options;  // threads = OpenMP threads per rank
  int steps = 20;
  int repeat = 5;
};

struct RankScalingResult {
  int ranks = 1;
  size_t elements = 0;
  std::vector<size_t> cuts;      // the slabs' element columns
  double one_rank_step_s = 0.0;  // median, whole mesh on one rank
  double spread_step_s = 0.0;    // median, the mesh over the ranks
  double speedup = 0.0;          // median of the repeats' ratios one_rank / spread
  double min_speedup = 0.0, max_speedup = 0.0;
  std::vector<double> halo_bytes_per_step;  // sent per step, per rank
  std::vector<double> halo_wait_fraction;   // per rank: of the step, waiting for the neighbours' planes
  double one_rank_seconds_per_element_step = 0.0;
  // Each slab as a mesh of its own, all ranks at once (no exchange): the machine's ceiling.
  double alone_step_s = 0.0;              // median, the slowest rank's
  double ceiling_speedup = 0.0;           // median of the repeats' ratios one_rank / alone
  std::vector<double> slab_alone_step_s;  // per rank, its own slab's mean step
};
/// Collective over comm (every rank calls it with the same spec); the result is complete on rank 0.
RankScalingResult runRankScaling(const RankScalingSpec& spec, const std::shared_ptr<SoilComm>& comm);

/// Fused multiply-add peak of this machine (independent register FMAs in the widest vectors the stiffness
/// kernels use), GFLOP/s (2 flops per FMA), with `threads` threads, median of `repeat` runs of ~0.1 s.
struct FmaPeak {
  std::string instruction_set;  // "avx512f", "avx2+fma" or "sse2 (mul + add)"
  int threads = 1;
  double gflop_s = 0.0;  // all threads
  double per_core_gflop_s = 0.0;
};
FmaPeak measureFmaPeak(Precision precision, int threads, int repeat = 5);

}  // namespace railvib::soil
