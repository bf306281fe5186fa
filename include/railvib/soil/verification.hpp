// railvib/soil: verification problems shared by the unit tests and
// `railvib_tool soil-bench` (column, damping decay, throughput, Lamb).
#pragma once

#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"
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

struct ThroughputResult {
  size_t elements = 0;
  size_t boundary_elements = 0;  // integrated by the boundary's unit (a PML), not the kernel
  int threads = 0;
  double element_updates_per_s = 0.0;      // wall clock
  double element_updates_per_cpu_s = 0.0;  // per CPU second of the process (user + sys, all threads)
  double seconds_per_step = 0.0;
};
/// Time `steps` steps of an nx x ny x nz homogeneous box with Lysmer faces (or the given boundary).
ThroughputResult runThroughput(size_t nx, size_t ny, size_t nz, int threads, Precision precision, int steps,
                               const BoundarySpec& boundary = BoundarySpec{});

}  // namespace railvib::soil
