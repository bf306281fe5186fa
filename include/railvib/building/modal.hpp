// railvib/building: modal analysis (sparse shift-invert Lanczos).
//
// K phi = w^2 M phi with the lumped (positive semi-definite) mass, solved as
// the symmetric standard problem  M^1/2 (K - sigma M)^-1 M^1/2 z = nu z,
// nu = 1/(w^2 - sigma), with Spectra's Lanczos solver and a CHOLMOD
// supernodal Cholesky factorisation of K - sigma M (done once).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "railvib/building/model.hpp"

namespace railvib::building {

struct Mode {
  double frequency_hz = 0.0;
  Eigen::VectorXd shape;  ///< all DOFs (zeros on constrained ones), mass-normalised
  Eigen::Vector3d effective_mass_kg = Eigen::Vector3d::Zero();  ///< x, y, z base translation
  double torsion_mass_fraction = 0.0;  ///< effective rotational inertia about z / total (free DOFs)
  std::string label;
  /// Mesh group of the slab whose out-of-plane bending carries the most kinetic energy when the slabs
  /// outweigh the walls ("slab_0", "slab_1", ..., "roof", "base_slab"); empty for wall, sway and torsion modes.
  std::string bending_slab;
  double symmetry_x = 0.0;  ///< +1 symmetric / -1 antisymmetric about the plane x = mid-length
  double symmetry_y = 0.0;  ///< about the plane y = mid-width
  bool symmetric = false;   ///< symmetric about both vertical mid-planes
};

struct ModalOptions {
  double fmax_hz = 50.0;
  bool fixed_base = true;  ///< false: free-free model (rigid-body check)
  int min_modes = 10;
  int max_modes = 400;
};

struct ModalResult {
  std::vector<Mode> modes;    ///< ascending frequency, all below fmax (at least min_modes)
  double free_mass_kg = 0.0;  ///< translational mass of the free DOFs (per direction)
  Eigen::Vector3d cumulative_effective_mass_fraction = Eigen::Vector3d::Zero();
  int dof_count = 0;  ///< free DOFs
  double seconds = 0.0;
};

ModalResult modalAnalysis(const BuildingModel& model, const ModalOptions& options = {});

/// Lowest `count` natural frequencies (Hz) of K x = w^2 diag(m) x (m >= 0, K - sigma diag(m) positive
/// definite), with the same shift-invert Lanczos solver. Used for element tests on small models.
std::vector<double> lowestFrequencies(const Eigen::SparseMatrix<double>& k, const Eigen::VectorXd& m, int count,
                                      double sigma = 0.0);

/// What a mode is, from its kinetic energy distribution: a label ("first floor bending (1,1)", "sway y
/// (across the width)", ...) and the slab that bends most (Mode::bending_slab).
struct ModeDescription {
  std::string label;
  std::string slab_group;
};
/// Mesh group of the paper's "upper floor" (section 3.4; "first floor" in Fig. 14, "upper floor" in Fig. 15):
/// the slab above the ground floor ("slab_1"), or the roof slab of a one-storey house; empty if there is none.
std::string upperFloorSlab(const BuildingParams& params);
/// The upper floor's own first bending (the paper's 15.0 Hz mode): the lowest doubly symmetric mode in
/// which that slab bends most; nullptr if there is none.
const Mode* upperFloorBending(const ModalResult& result, const BuildingParams& params);

ModeDescription describeMode(const BuildingModel& model, const Mode& mode, double total_mass_kg);

}  // namespace railvib::building
