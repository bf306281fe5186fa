#include "railvib/building/modal.hpp"

#include <Spectra/SymEigsSolver.h>

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "railvib/common/constants.hpp"

namespace railvib::building {
namespace {

/// y = M^1/2 (K - sigma M)^-1 M^1/2 x on the free DOFs.
class ShiftInvertOp {
 public:
  using Scalar = double;
  ShiftInvertOp(const Eigen::SparseMatrix<double>& k, const Eigen::VectorXd& m, double sigma) : mh_(m.cwiseSqrt()) {
    Eigen::SparseMatrix<double> a = k;
    for (int i = 0; i < a.rows(); ++i) a.coeffRef(i, i) -= sigma * m[i];
    llt_.compute(a);
    if (llt_.info() != Eigen::Success) throw std::runtime_error("modal analysis: K - sigma M is not positive definite");
  }
  Eigen::Index rows() const { return mh_.size(); }
  Eigen::Index cols() const { return mh_.size(); }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    const Eigen::VectorXd b = mh_.cwiseProduct(x);
    y = mh_.cwiseProduct(llt_.solve(b));
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const { return llt_.solve(b); }

 private:
  Eigen::VectorXd mh_;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt_;
};

Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double>& k, const std::vector<int>& index, int n) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(k.nonZeros());
  for (int c = 0; c < k.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it) {
      const int r = index[it.row()], cc = index[it.col()];
      if (r >= 0 && cc >= 0) t.emplace_back(r, cc, it.value());
    }
  Eigen::SparseMatrix<double> out(n, n);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

int signChanges(std::vector<std::pair<double, double>> samples) {
  std::sort(samples.begin(), samples.end());
  double amax = 0.0;
  for (auto& s : samples) amax = std::max(amax, std::abs(s.second));
  int changes = 0;
  int last = 0;
  for (auto& s : samples) {
    if (std::abs(s.second) < 0.05 * amax) continue;
    const int sg = s.second > 0 ? 1 : -1;
    if (last != 0 && sg != last) ++changes;
    last = sg;
  }
  return changes;
}

}  // namespace

std::string upperFloorSlab(const BuildingParams& params) {
  if (params.storeys >= 2) return "slab_1";
  return params.roof_slab ? "roof" : "";
}

const Mode* upperFloorBending(const ModalResult& result, const BuildingParams& params) {
  const std::string slab = upperFloorSlab(params);
  if (slab.empty()) return nullptr;
  for (const Mode& m : result.modes)
    if (m.symmetric && m.bending_slab == slab) return &m;
  return nullptr;
}

ModeDescription describeMode(const BuildingModel& model, const Mode& mode, double total_mass_kg) {
  const BuildingMesh& mesh = model.mesh();
  const Eigen::VectorXd& m = model.mass();
  const Eigen::VectorXd& phi = mode.shape;
  // Out-of-plane kinetic energy per group (slabs: z, front/back walls: y, left/right: x).
  std::map<std::string, double> energy;
  std::vector<int> node_group(mesh.nodes.size(), -1);
  for (const MeshElement& e : mesh.elements)
    for (int a : e.nodes)
      if (node_group[a] < 0 || mesh.groups[e.group].rfind("slab", 0) == 0 || mesh.groups[e.group] == "roof")
        node_group[a] = e.group;
  double total = 0.0;
  for (size_t n = 0; n < mesh.nodes.size(); ++n) {
    double en = 0.0;
    for (int d = 0; d < 3; ++d) en += m[6 * n + d] * phi[6 * n + d] * phi[6 * n + d];
    total += en;
    if (node_group[n] < 0) continue;
    const std::string& g = mesh.groups[node_group[n]];
    int comp = 2;
    if (g == "wall_front" || g == "wall_back" || g == "wall_interior_x") comp = 1;
    if (g == "wall_left" || g == "wall_right" || g == "wall_interior_y") comp = 0;
    energy[g] += m[6 * n + comp] * phi[6 * n + comp] * phi[6 * n + comp];
  }
  if (total <= 0.0) return {"none", ""};
  const Eigen::Vector3d frac = mode.effective_mass_kg / total_mass_kg;
  if (mode.torsion_mass_fraction > 0.2) return {"torsion", ""};
  if (frac.x() > 0.2) return {"sway x (along the length)", ""};
  if (frac.y() > 0.2) return {"sway y (across the width)", ""};
  double slab_e = 0.0, wall_e = 0.0;
  std::string best_slab;
  double best_slab_e = 0.0;
  std::vector<std::string> walls;
  for (auto& [g, e] : energy) {
    if (g.rfind("slab", 0) == 0 || g == "roof" || g == "base_slab") {
      slab_e += e;
      if (e > best_slab_e) {
        best_slab_e = e;
        best_slab = g;
      }
    } else if (g.rfind("wall", 0) == 0) {
      wall_e += e;
      if (e > 0.15 * total) walls.push_back(g.substr(5));
    }
  }
  std::ostringstream os;
  ModeDescription out;
  if (slab_e >= wall_e && !best_slab.empty()) {
    out.slab_group = best_slab;
    // half-wave numbers along the slab's centre lines
    // lines at 30 % of the span: off every nodal line of the low (m, n) modes
    const double xq = mesh.x0_m + 0.3 * (mesh.x1_m - mesh.x0_m), yq = mesh.y0_m + 0.3 * (mesh.y1_m - mesh.y0_m);
    const double tol = 0.51 * mesh.element_size_m;
    std::vector<std::pair<double, double>> along_x, along_y;
    double zslab = 0.0;
    for (const MeshElement& e : mesh.elements)
      if (mesh.groups[e.group] == best_slab) zslab = mesh.nodes[e.nodes[0]].z();
    for (size_t n = 0; n < mesh.nodes.size(); ++n) {
      const Eigen::Vector3d& x = mesh.nodes[n];
      if (std::abs(x.z() - zslab) > 1e-9) continue;
      // strongest line parallel to x / y through the slab: use the quarter and centre lines
      if (std::abs(x.y() - yq) < tol) along_x.emplace_back(x.x(), phi[6 * n + 2]);
      if (std::abs(x.x() - xq) < tol) along_y.emplace_back(x.y(), phi[6 * n + 2]);
    }
    const int mx = signChanges(along_x) + 1;
    const int my = signChanges(along_y) + 1;
    const std::string name = best_slab == "roof"        ? "roof slab"
                             : best_slab == "slab_0"    ? "ground floor"
                             : best_slab == "base_slab" ? "base slab"
                             : best_slab == "slab_1"    ? "first floor"
                                                        : best_slab;
    os << name << " bending (" << mx << "," << my << ")";
    if (wall_e > 0.3 * total) os << " + wall flexure";
  } else {
    os << "wall flexure";
    if (!walls.empty()) {
      os << " (";
      for (size_t i = 0; i < walls.size(); ++i) os << (i ? "+" : "") << walls[i];
      os << ")";
    }
    if (slab_e > 0.3 * total) os << " + floor bending";
  }
  out.label = os.str();
  return out;
}

std::vector<double> lowestFrequencies(const Eigen::SparseMatrix<double>& k, const Eigen::VectorXd& m, int count,
                                      double sigma) {
  ShiftInvertOp op(k, m, sigma);
  int massive = 0;
  for (int i = 0; i < m.size(); ++i) massive += m[i] > 0.0 ? 1 : 0;
  const int nev = std::min(count, massive - 2);
  Spectra::SymEigsSolver<ShiftInvertOp> solver(op, nev, std::min(massive, std::max(2 * nev + 1, nev + 20)));
  solver.init();
  solver.compute(Spectra::SortRule::LargestAlge, 2000, 1e-10, Spectra::SortRule::LargestAlge);
  if (solver.info() != Spectra::CompInfo::Successful) throw std::runtime_error("eigen solver did not converge");
  std::vector<double> f;
  for (int j = 0; j < solver.eigenvalues().size(); ++j)
    f.push_back(std::sqrt(std::max(sigma + 1.0 / solver.eigenvalues()[j], 0.0)) / kTwoPi);
  return f;
}

ModalResult modalAnalysis(const BuildingModel& model, const ModalOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const int ndof = model.dofCount();
  std::vector<int> index(ndof);
  std::vector<int> dofs;
  if (opt.fixed_base) {
    index = model.freeIndex();
    dofs = model.freeDofs();
  } else {
    std::iota(index.begin(), index.end(), 0);
    dofs = index;
  }
  const int n = static_cast<int>(dofs.size());
  const Eigen::SparseMatrix<double> k = restrict(model.stiffness(), index, n);
  Eigen::VectorXd m(n);
  for (int i = 0; i < n; ++i) m[i] = model.mass()[dofs[i]];
  // Fixed base: K is positive definite, shift at 0. Free: shift below zero to step over the rigid-body modes.
  const double sigma = opt.fixed_base ? 0.0 : -std::pow(kTwoPi * 1.0, 2);
  ShiftInvertOp op(k, m, sigma);
  int massive = 0;
  for (int i = 0; i < n; ++i) massive += m[i] > 0.0 ? 1 : 0;

  ModalResult result;
  result.dof_count = n;
  const double lambda_max = std::pow(kTwoPi * opt.fmax_hz, 2);
  int nev = std::max(opt.min_modes, 30);
  Eigen::VectorXd evals;
  Eigen::MatrixXd evecs;
  while (true) {
    nev = std::min(nev, std::max(1, massive - 2));
    const int ncv = std::min(massive, std::max(2 * nev + 1, nev + 20));
    Spectra::SymEigsSolver<ShiftInvertOp> solver(op, nev, ncv);
    solver.init();
    solver.compute(Spectra::SortRule::LargestAlge, 2000, 1e-10, Spectra::SortRule::LargestAlge);
    if (solver.info() != Spectra::CompInfo::Successful)
      throw std::runtime_error("modal analysis: Lanczos did not converge");
    evals = solver.eigenvalues();
    evecs = solver.eigenvectors();
    const double last_lambda = sigma + 1.0 / evals[evals.size() - 1];
    if (last_lambda > lambda_max || nev >= opt.max_modes || nev >= massive - 2) break;
    nev = std::min(opt.max_modes, 2 * nev);
  }

  const Eigen::VectorXd mh = m.cwiseSqrt();
  // Influence vectors (free DOFs): unit base translations and rotation about the vertical centre line.
  const BuildingMesh& mesh = model.mesh();
  const double xc = 0.5 * (mesh.x0_m + mesh.x1_m), yc = 0.5 * (mesh.y0_m + mesh.y1_m);
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(n, 4);
  for (int i = 0; i < n; ++i) {
    const int g = dofs[i];
    const int comp = g % 6;
    const Eigen::Vector3d& x = mesh.nodes[g / 6];
    if (comp < 3) r(i, comp) = 1.0;
    if (comp == 0) r(i, 3) = -(x.y() - yc);
    if (comp == 1) r(i, 3) = x.x() - xc;
    if (comp == 5) r(i, 3) = 1.0;
  }
  double free_mass = 0.0, inertia_z = 0.0;
  for (int i = 0; i < n; ++i) {
    if (dofs[i] % 6 == 2) free_mass += m[i];
    inertia_z += m[i] * r(i, 3) * r(i, 3);
  }
  result.free_mass_kg = free_mass;

  for (int j = 0; j < evals.size(); ++j) {
    const double lambda = sigma + 1.0 / evals[j];
    if (lambda > lambda_max && static_cast<int>(result.modes.size()) >= opt.min_modes) break;
    Mode mode;
    mode.frequency_hz = std::sqrt(std::max(lambda, 0.0)) / kTwoPi;
    // phi = (K - sigma M)^-1 M^1/2 z / nu
    Eigen::VectorXd phi = op.solve(mh.cwiseProduct(evecs.col(j))) / evals[j];
    const double mn = phi.dot(m.cwiseProduct(phi));
    phi /= std::sqrt(mn);
    const Eigen::VectorXd mphi = m.cwiseProduct(phi);
    for (int d = 0; d < 3; ++d) mode.effective_mass_kg[d] = std::pow(mphi.dot(r.col(d)), 2);
    mode.torsion_mass_fraction = inertia_z > 0.0 ? std::pow(mphi.dot(r.col(3)), 2) / inertia_z : 0.0;
    mode.shape = Eigen::VectorXd::Zero(ndof);
    for (int i = 0; i < n; ++i) mode.shape[dofs[i]] = phi[i];
    // Symmetry: phi . M . (mirror phi)
    for (int axis = 0; axis < 2; ++axis) {
      const std::vector<int>& mir = model.mirror(axis);
      double s = 0.0;
      for (size_t nn = 0; nn < mesh.nodes.size(); ++nn) {
        const int q = mir[nn];
        if (q < 0) continue;
        for (int d = 0; d < 3; ++d) {
          const double sign = (d == axis) ? -1.0 : 1.0;
          s += model.mass()[6 * nn + d] * mode.shape[6 * nn + d] * sign * mode.shape[6 * q + d];
        }
      }
      (axis == 0 ? mode.symmetry_x : mode.symmetry_y) = s;
    }
    mode.symmetric = mode.symmetry_x > 0.5 && mode.symmetry_y > 0.5;
    result.cumulative_effective_mass_fraction += mode.effective_mass_kg / free_mass;
    result.modes.push_back(std::move(mode));
  }
  for (Mode& mode : result.modes) {
    if (mode.frequency_hz < 1e-3 * opt.fmax_hz) {
      mode.label = "rigid body";
      continue;
    }
    ModeDescription d = describeMode(model, mode, free_mass);
    mode.label = std::move(d.label);
    mode.bending_slab = std::move(d.slab_group);
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace railvib::building
