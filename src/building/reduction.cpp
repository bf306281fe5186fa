#include "railvib/building/reduction.hpp"

#include <Eigen/CholmodSupport>
#include <stdexcept>

#include "railvib/building/modal.hpp"
#include "railvib/common/constants.hpp"

namespace railvib::building {

namespace {}

Eigen::MatrixXd rigidMotionMap(const BuildingModel& model, const Eigen::Vector3d& reference_m) {
  const auto& nodes = model.mesh().nodes;
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(model.dofCount(), 6);
  for (size_t n = 0; n < nodes.size(); ++n) {
    const Eigen::Vector3d a = nodes[n] - reference_m;
    const int d = static_cast<int>(n) * kDofPerNode;
    // U + Theta x a: columns of Theta give (Theta x a) = -a x Theta = -S(a) Theta.
    r.block<3, 3>(d, 0).setIdentity();
    r.block<3, 3>(d, 3) << 0.0, a.z(), -a.y(), -a.z(), 0.0, a.x(), a.y(), -a.x(), 0.0;
    r.block<3, 3>(d + 3, 3).setIdentity();
  }
  return r;
}

RigidBaseReduction reduceOnRigidBase(const BuildingModel& model, double fmax_hz, const Eigen::Vector3d& reference_m) {
  RigidBaseReduction red;
  red.reference_m = reference_m;
  red.fmax_hz = fmax_hz;
  const Eigen::MatrixXd r = rigidMotionMap(model, reference_m);
  const Eigen::VectorXd& m = model.mass();
  const std::vector<int>& free = model.freeDofs();
  const std::vector<int>& fixed = model.constrainedDofs();
  for (int d : free) red.superstructure_rigid_mass += m[d] * r.row(d).transpose() * r.row(d);
  for (int d : fixed) red.foundation_rigid_mass += m[d] * r.row(d).transpose() * r.row(d);

  // Constraint modes -K_ff^-1 K_fc R_c against the rigid motion R_f of the free DOFs.
  const std::vector<int>& fi = model.freeIndex();
  std::vector<int> ci(model.dofCount(), -1);
  for (size_t q = 0; q < fixed.size(); ++q) ci[fixed[q]] = static_cast<int>(q);
  std::vector<Eigen::Triplet<double>> tff, tfc;
  const Eigen::SparseMatrix<double>& k = model.stiffness();
  for (int c = 0; c < k.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it) {
      const int row = fi[it.row()];
      if (row < 0) continue;
      if (fi[it.col()] >= 0)
        tff.emplace_back(row, fi[it.col()], it.value());
      else
        tfc.emplace_back(row, ci[it.col()], it.value());
    }
  }
  const int nf = static_cast<int>(free.size()), nc = static_cast<int>(fixed.size());
  Eigen::SparseMatrix<double> kff(nf, nf), kfc(nf, nc);
  kff.setFromTriplets(tff.begin(), tff.end());
  kfc.setFromTriplets(tfc.begin(), tfc.end());
  Eigen::MatrixXd rc(nc, 6), rf(nf, 6);
  for (int q = 0; q < nc; ++q) rc.row(q) = r.row(fixed[q]);
  for (int q = 0; q < nf; ++q) rf.row(q) = r.row(free[q]);
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt(kff);
  if (llt.info() != Eigen::Success) throw std::runtime_error("rigid-base reduction: K_ff is not positive definite");
  const Eigen::MatrixXd psi = -llt.solve(Eigen::MatrixXd(kfc * rc));
  for (int c = 0; c < 6; ++c) {
    red.constraint_mode_error =
        std::max(red.constraint_mode_error, (psi.col(c) - rf.col(c)).norm() / std::max(1e-300, rf.col(c).norm()));
  }

  // Fixed-interface (fixed-base) modes.
  ModalOptions options;
  options.fmax_hz = fmax_hz;
  options.min_modes = 1;
  const ModalResult modes = modalAnalysis(model, options);
  const int nm = static_cast<int>(modes.modes.size());
  red.shapes.resize(model.dofCount(), nm);
  red.circular_frequency_rad_s.resize(nm);
  red.damping_ratio.resize(nm);
  red.participation.resize(nm, 6);
  const BuildingParams& p = model.params();
  const RayleighCoefficients rayleigh = rayleighCoefficients(p);
  const double alpha = rayleigh.alpha_1_s, beta = rayleigh.beta_s;
  for (int i = 0; i < nm; ++i) {
    const Mode& mode = modes.modes[static_cast<size_t>(i)];
    const double w = kTwoPi * mode.frequency_hz;
    red.shapes.col(i) = mode.shape;
    red.circular_frequency_rad_s[i] = w;
    red.damping_ratio[i] = alpha / (2.0 * w) + beta * w / 2.0;
    red.participation.row(i) = (mode.shape.cwiseProduct(m)).transpose() * r;
  }
  return red;
}

Eigen::VectorXd reducedResponse(const BuildingModel& model, const RigidBaseReduction& red,
                                const Eigen::Matrix<double, 6, 1>& base_velocity,
                                const Eigen::VectorXd& modal_velocity) {
  const auto& points = model.responseNodes();
  Eigen::VectorXd out(3 * static_cast<Eigen::Index>(points.size()));
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d a = points[i].position - red.reference_m;
    const Eigen::Vector3d rigid = base_velocity.head<3>() + base_velocity.tail<3>().cross(a);
    for (int c = 0; c < 3; ++c) {
      const int d = points[i].node * kDofPerNode + c;
      out[3 * static_cast<Eigen::Index>(i) + c] = rigid[c] + red.shapes.row(d).dot(modal_velocity);
    }
  }
  return out;
}

}  // namespace railvib::building
