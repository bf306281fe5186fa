// railvib/building: the house reduced on a rigid foundation, for soil-structure interaction.
//
// Craig-Bampton reduction (Craig & Bampton, AIAA J. 6(7), 1968) with the
// foundation box (the DOFs the one-way model drives) as a rigid interface of
// 6 DOFs q = (U, Theta) at a reference point, building frame (x along, y
// across, z up), right-handed rotations: a node at offset r moves
// U + Theta x r and turns Theta. The constraint modes are then the static
// response of the superstructure to unit rigid motions, which is the rigid
// motion itself (no strain); the fixed-interface modes are the fixed-base
// modes. Reduced equations of the superstructure on its moving base:
//   M_bb q'' + L^T eta'' = -(force on the base),   eta'' + 2 z w eta' + w^2 eta = -L q''
// with M_bb = R^T M R over the free DOFs, L = Phi^T M R, and z the modal
// damping ratio of the house's Rayleigh damping (which acts on the motion
// relative to the rigid base, building/response.hpp).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "railvib/building/model.hpp"

namespace railvib::building {

struct RigidBaseReduction {
  Eigen::Vector3d reference_m = Eigen::Vector3d::Zero();  ///< building frame
  double fmax_hz = 0.0;                                   ///< highest fixed-interface mode kept
  /// R^T M R of the free DOFs (the superstructure) and of the foundation DOFs, about the reference point.
  Eigen::Matrix<double, 6, 6> superstructure_rigid_mass = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 6> foundation_rigid_mass = Eigen::Matrix<double, 6, 6>::Zero();
  /// L = Phi^T M R (modes x 6), circular frequencies (rad/s), damping ratios.
  Eigen::MatrixXd participation;
  Eigen::VectorXd circular_frequency_rad_s;
  Eigen::VectorXd damping_ratio;
  /// Mode shapes on all DOFs (zeros on the foundation DOFs), mass-normalised (DOFs x modes).
  Eigen::MatrixXd shapes;
  /// Largest |constraint mode - rigid motion| / |rigid motion| over the 6 constraint modes
  /// (-K_ff^-1 K_fc R_c against R_f): ~1e-12 when the foundation is a rigid interface.
  double constraint_mode_error = 0.0;
  int modeCount() const { return static_cast<int>(circular_frequency_rad_s.size()); }
};

/// Rigid-motion map (dofCount x 6) of every DOF for a reference point (building frame).
Eigen::MatrixXd rigidMotionMap(const BuildingModel& model, const Eigen::Vector3d& reference_m);

/// The reduction with the fixed-base modes up to fmax_hz (all of them: at least one).
RigidBaseReduction reduceOnRigidBase(const BuildingModel& model, double fmax_hz, const Eigen::Vector3d& reference_m);

/// Velocities (vx, vy, vz; m/s) of the response points from the rigid base velocity q' and modal velocities.
Eigen::VectorXd reducedResponse(const BuildingModel& model, const RigidBaseReduction& reduction,
                                const Eigen::Matrix<double, 6, 1>& base_velocity,
                                const Eigen::VectorXd& modal_velocity);

}  // namespace railvib::building
