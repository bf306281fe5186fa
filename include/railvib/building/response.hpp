// railvib/building: response of the house to the motion of the soil at its footprint.
//
// One-way multi-support excitation: the nodes of the foundation box follow
// the soil surface velocity, interpolated bilinearly in plan from the
// footprint receivers (footprintPoints(), same order), with the rotations
// of that interpolated field. The superstructure is integrated with the
// implicit Newmark average-acceleration rule (unconditionally stable), its
// matrix factorised once (CHOLMOD). Rayleigh damping [assumed] acts on the
// motion relative to the quasi-static (pseudo-static) response, so that a
// rigid motion of the foundation carries the building without damping forces.
//
// Streaming use (e.g. by building_node):
//   BuildingResponseSolver solver(model, 1.0 / soil_rate_hz);
//   for each block:  Eigen::MatrixXd out = solver.process(first_index, footprint_velocities);
// footprint_velocities: one row per sample, 3 columns per footprint point
// (vx, vy, vz in m/s, track frame = building frame axes), in footprintPoints() order.
// out: one row per sample, 3 columns per response point (vx, vy, vz, m/s), in
// responsePoints() order (the configured points plus any added with addPoint()).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <complex>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "railvib/building/model.hpp"
#include "railvib/common/sample_stream.hpp"

namespace railvib::building {

/// The rigid motion (U, Theta: 6 DOFs, building frame, about the plan centre on the ground surface) least-squares
/// fitted to velocities at the footprint points (3 per point, footprintPoints() order): a 6 x 3n matrix, exact for
/// a rigid motion. The two-way coupling drives the house with it.
Eigen::MatrixXd footprintRigidFit(const BuildingParams& params);

class BuildingResponseSolver {
 public:
  /// sample_period_s: period of the footprint velocity samples; the solver sub-steps
  /// internally so that its step does not exceed building.solver.max_time_step_s.
  BuildingResponseSolver(const BuildingModel& model, double sample_period_s);
  ~BuildingResponseSolver();
  BuildingResponseSolver(const BuildingResponseSolver&) = delete;
  BuildingResponseSolver& operator=(const BuildingResponseSolver&) = delete;

  const std::vector<FootprintPoint>& footprint() const { return footprint_; }
  size_t inputColumns() const { return 3 * footprint_.size(); }
  /// Output points (configured response points, then added ones).
  const std::vector<ResponseNode>& responsePoints() const { return points_; }
  std::vector<std::string> outputColumnNames() const;  ///< "<name>_vx", "<name>_vy", "<name>_vz"...
  /// Add an output point (building frame) before the first block; throws ConfigError if off the structure.
  void addPoint(const NamedPoint& point);

  /// Process a block whose first sample has index `first_sample`; throws StreamGapError on a gap.
  Eigen::MatrixXd process(uint64_t first_sample, const Eigen::MatrixXd& footprint_velocity);
  /// Process the next block (continuation of the previous one).
  Eigen::MatrixXd process(const Eigen::MatrixXd& footprint_velocity) {
    return process(tracker_.nextIndex(), footprint_velocity);
  }
  uint64_t nextSample() const { return tracker_.nextIndex(); }
  double samplePeriod() const { return sample_period_s_; }
  int substeps() const { return substeps_; }
  double rayleighAlpha() const { return alpha_; }
  double rayleighBeta() const { return beta_; }
  /// Back to rest at sample 0.
  void reset();

 private:
  struct Impl;
  void step(const Eigen::VectorXd& qd_new, double dt);
  Eigen::VectorXd output() const;

  const BuildingModel& model_;
  std::vector<FootprintPoint> footprint_;
  std::vector<ResponseNode> points_;
  double sample_period_s_;
  int substeps_ = 1;
  double alpha_ = 0.0, beta_ = 0.0;
  SampleIndexTracker tracker_;
  std::unique_ptr<Impl> impl_;
};

/// Transfer functions from a uniform vertical foundation velocity to the vertical
/// velocity of the response points, by an impulse (impact) analysis through
/// BuildingResponseSolver and a discrete Fourier transform of both signals.
struct TransferFunctionOptions {
  double duration_s = 6.0;
  double sample_period_s = 1.0e-3;
  double pulse_duration_s = 0.01;  ///< half-sine velocity pulse
  double fmax_hz = 60.0;
  double df_hz = 0.05;
};

struct TransferFunctions {
  std::vector<std::string> names;
  std::vector<double> frequency_hz;
  Eigen::MatrixXcd tf;                ///< frequency x point
  Eigen::VectorXd base_velocity;      ///< input pulse (m/s) per sample
  Eigen::MatrixXd response_velocity;  ///< vertical velocity per sample x point
};

TransferFunctions impulseTransferFunctions(const BuildingModel& model, const TransferFunctionOptions& options = {});

}  // namespace railvib::building
