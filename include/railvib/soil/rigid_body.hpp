// railvib/soil: a rigid body carried by soil nodes, with an optional reduced
// superstructure on it (soil-structure interaction, two-way).
//
// Every soil node inside a box region (a surface footing when depth_m is 0, an
// embedded foundation otherwise) moves with the body:
//   u_a = u + omega x (r_a - r_ref)
// with q = (u, omega) the 6 rigid degrees of freedom at the reference point,
// all in the solver's internal frame (x, y, d = depth down; cross products
// by components). Elements inside the region then carry no strain, so the
// body's stiffness and radiation come from the surrounding soil; its mass is
// the carried nodes' soil mass plus `added_mass` (e.g. concrete minus the
// displaced soil). The superstructure is a Craig-Bampton reduction on a rigid
// interface (Craig & Bampton, AIAA J. 6(7), 1968): its constraint modes are
// the 6 rigid-body modes (mass matrix `structure.rigid_mass`), its
// fixed-interface modes eta_i (mass-normalised, circular frequency w_i,
// damping ratio z_i) couple through the participation L = Phi^T M R:
//   [M_body + M_bb  L^T] [q'']   [0      0   ] [q' ]   [0   0  ] [q  ]   [F]
//   [L              I  ] [eta''] + [0  2 z w ] [eta'] + [0  w^2 ] [eta] = [0]
// F = sum_a R_a^T f_a, the generalised force of the complete nodal forces
// (soil elements outside the region, loads) on the carried nodes. The system
// is advanced in lockstep with the soil by the same central difference in
// velocity form (damping averaged over the half steps), so the interface
// exchanges power exactly: the coupled system is passive.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <string>

namespace railvib::soil {

/// A superstructure reduced on a rigid base (all matrices in the soil's rigid-DOF convention).
struct ReducedStructure {
  /// R^T M R of the superstructure's free DOFs about the reference point (kg, kg m, kg m^2).
  Eigen::Matrix<double, 6, 6> rigid_mass = Eigen::Matrix<double, 6, 6>::Zero();
  /// L = Phi^T M R: one row per fixed-interface mode.
  Eigen::MatrixXd participation;
  Eigen::VectorXd circular_frequency_rad_s;
  Eigen::VectorXd damping_ratio;
  int modeCount() const { return static_cast<int>(circular_frequency_rad_s.size()); }
};

struct RigidBodySpec {
  std::string name = "foundation";
  /// Region of carried soil nodes (internal frame, m): x, y range and depth below the surface
  /// (0: the surface nodes only). Nodes within `snap_tolerance_m` of the region count as inside;
  /// with `snap_to_nearest` each face moves to the nearest node line/plane instead (a region that
  /// does not follow the mesh, e.g. a house).
  double x_min_m = 0.0, x_max_m = 0.0, y_min_m = 0.0, y_max_m = 0.0, depth_m = 0.0;
  double snap_tolerance_m = 1e-6;
  bool snap_to_nearest = false;
  /// > 0: only the nodes within this plan distance of the region's edge, rounded to whole elements (at
  /// least one), are carried: a ring, e.g. the tops of a foundation's walls that a house stands on.
  double ring_width_m = 0.0;
  /// Reference point of the rigid DOFs (internal frame: x, y, d).
  Eigen::Vector3d reference_m = Eigen::Vector3d::Zero();
  /// Mass added to the carried soil nodes (about the reference point).
  Eigen::Matrix<double, 6, 6> added_mass = Eigen::Matrix<double, 6, 6>::Zero();
  /// Rigid DOFs held at zero (e.g. by the symmetry planes of a quarter model): u_x, u_y, u_d, w_x, w_y, w_d.
  std::array<bool, 6> held{{false, false, false, false, false, false}};
  ReducedStructure structure;
};

/// State of a rigid body after a step: displacement q_{n+1} and half-step velocity q'_{n+1/2}.
struct RigidBodyState {
  Eigen::Matrix<double, 6, 1> displacement = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> velocity = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::VectorXd modal_displacement, modal_velocity;
  /// Generalised soil force F_n on the body in the last step.
  Eigen::Matrix<double, 6, 1> soil_force = Eigen::Matrix<double, 6, 1>::Zero();
  size_t carried_nodes = 0;
  /// Mass of the carried soil nodes (kg) and the body's total translational mass (kg).
  double carried_soil_mass_kg = 0.0, total_mass_kg = 0.0;
  /// Region as snapped to the mesh (internal frame).
  double x_min_m = 0.0, x_max_m = 0.0, y_min_m = 0.0, y_max_m = 0.0, depth_m = 0.0;
};

}  // namespace railvib::soil
