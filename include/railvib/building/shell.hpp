// railvib/building: flat 4-node shell element (6 DOF per node: ux uy uz rx ry rz, global axes).
//
// Membrane: bilinear quadrilateral with two condensed incompatible modes per
// direction (QM6, Taylor's constant-Jacobian variant), free of in-plane shear
// locking in bending of walls. Bending: Reissner-Mindlin plate with the MITC4
// assumed transverse shear strains (Bathe & Dvorkin), free of transverse shear
// locking for thin slabs and walls. Drilling rotation: tied by a small penalty
// to the in-plane rotation of the membrane field at each node, which keeps
// the six rigid-body modes exact. Mass: lumped, translational only.
#pragma once

#include <Eigen/Dense>
#include <array>

namespace railvib::building {

struct ShellSection {
  double young_modulus_pa = 0.0;
  double poisson = 0.0;
  double thickness_m = 0.0;
  double density_kg_m3 = 0.0;
  /// Drilling penalty as a fraction of G t A.
  double drilling_factor = 1.0e-3;
};

using ShellNodes = std::array<Eigen::Vector3d, 4>;
using ShellMatrix = Eigen::Matrix<double, 24, 24>;

/// Element stiffness in global axes, DOF order (node0: ux uy uz rx ry rz, node1: ...).
/// Nodes are the corners in circulation order; the element must be flat.
ShellMatrix shellStiffness(const ShellNodes& x, const ShellSection& section);

/// Integral of each bilinear shape function over the element (tributary areas, m^2).
std::array<double, 4> shellNodalAreas(const ShellNodes& x);

/// Largest distance of a corner from the mean plane divided by the diagonal (0 for a flat element).
double shellWarp(const ShellNodes& x);

}  // namespace railvib::building
