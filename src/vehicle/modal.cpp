#include "railvib/vehicle/modal.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/passage.hpp"

namespace railvib::vehicle {

namespace {

/// Category of each full-coordinate DOF and the body it belongs to.
struct DofLabels {
  std::vector<std::string> category;
  std::vector<std::string> body;
};

DofLabels labels(const VehicleModel& model) {
  DofLabels L;
  L.category.assign(static_cast<size_t>(model.fullDofCount()), "");
  L.body.assign(static_cast<size_t>(model.fullDofCount()), "");
  for (const auto& b : model.bodies()) {
    const std::string bogie = model.bogieLabel(b);
    const auto& wheels = model.wheels();
    const bool motor = b.index < static_cast<int>(wheels.size()) && wheels[b.index].type == AxleType::Motor;
    switch (b.kind) {
      case BodyKind::Carbody:
        L.category[b.z_dof] = "car-body bounce";
        L.category[b.theta_dof] = "car-body pitch";
        break;
      case BodyKind::Bogie:
        L.category[b.z_dof] = bogie + " bounce";
        L.category[b.theta_dof] = bogie + " pitch";
        break;
      case BodyKind::WheelHub:
        L.category[b.z_dof] = std::string("axle hop (") + (motor ? "motor" : "trailer") + " wheels, " + bogie + ")";
        break;
      case BodyKind::Tread:
        L.category[b.z_dof] = "tread on resilient ring (" + bogie + ")";
        break;
      case BodyKind::Wheel:
        L.category[b.z_dof] = std::string("axle hop (") + (motor ? "motor" : "trailer") + " wheel, " + bogie + ")";
        break;
    }
    L.body[b.z_dof] = b.name;
    if (b.theta_dof >= 0) L.body[b.theta_dof] = b.name;
  }
  return L;
}

/// Name a mode from its reduced vehicle shape (complex).
void nameMode(const VehicleModel& model, const DofLabels& L, const Eigen::VectorXcd& shape_reduced, Mode& mode) {
  const Eigen::VectorXcd full = model.transform().cast<std::complex<double>>() * shape_reduced;
  const Eigen::VectorXd& m = model.fullMassDiagonal();
  std::map<std::string, double> by_cat, by_body;
  double total = 0.0;
  for (Eigen::Index i = 0; i < full.size(); ++i) {
    const double e = m[i] * std::norm(full[i]);
    by_cat[L.category[i]] += e;
    by_body[L.body[i]] += e;
    total += e;
  }
  auto best = [](const std::map<std::string, double>& mp) {
    return std::max_element(mp.begin(), mp.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  };
  const auto c = best(by_cat);
  mode.name = c->first;
  mode.name_share = total > 0.0 ? c->second / total : 0.0;
  mode.body = best(by_body)->first;

  // Bogie bounce vs pitch from the kinematics: the point of zero vertical motion
  // w = z + (s - s_c) theta = 0, i.e. s - s_c = -z / theta (in the least-squares
  // sense for a complex shape).
  for (const BodyInfo& b : model.bodies()) {
    if (b.kind != BodyKind::Bogie || b.name != mode.body) continue;
    const std::complex<double> z = full[b.z_dof], theta = full[b.theta_dof];
    const std::string bogie = model.bogieLabel(b);
    const bool named_after_this_bogie = mode.name == bogie + " bounce" || mode.name == bogie + " pitch";
    if (!named_after_this_bogie) break;
    const double half_wheelbase_m = b.half_wheelbase_m;
    if (half_wheelbase_m * std::abs(theta) < 0.01 * std::abs(z)) {
      mode.name = bogie + " bounce";  // the axles move within 1 % alike: no pivot to speak of
    } else {
      mode.pivot_offset_m = -std::real(z * std::conj(theta)) / std::norm(theta);
      mode.name = bogie + (std::abs(mode.pivot_offset_m) <= half_wheelbase_m * (1.0 + 1e-9) ? " pitch" : " bounce");
    }
    mode.name_share = total > 0.0 ? (by_cat[bogie + " bounce"] + by_cat[bogie + " pitch"]) / total : 0.0;
    break;
  }
}

/// Damped modes of (M, C, K) from the state-space eigenproblem; returns
/// eigenvalues with positive imaginary part and their displacement shapes.
void dampedModes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& C, const Eigen::MatrixXd& K,
                 std::vector<std::complex<double>>& lambdas, std::vector<Eigen::VectorXcd>& shapes) {
  const Eigen::Index n = M.rows();
  const Eigen::MatrixXd Minv = M.llt().solve(Eigen::MatrixXd::Identity(n, n));
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -Minv * K;
  A.bottomRightCorner(n, n) = -Minv * C;
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, true);
  if (es.info() != Eigen::Success) throw std::runtime_error("modal analysis: eigen solver failed");
  for (Eigen::Index k = 0; k < 2 * n; ++k) {
    const std::complex<double> l = es.eigenvalues()[k];
    if (l.imag() <= 1e-9 * std::abs(l)) continue;  // conjugates and overdamped (real) roots
    lambdas.push_back(l);
    shapes.push_back(es.eigenvectors().col(k).head(n));
  }
}

Mode modeFrom(std::complex<double> l) {
  Mode m;
  m.frequency_hz = std::abs(l) / (2.0 * M_PI);
  m.damping_ratio = -l.real() / std::abs(l);
  return m;
}

std::vector<double> wheelPositions(const VehicleModel& model, double front) {
  std::vector<double> x;
  for (const auto& w : model.wheels()) x.push_back(front - w.offset_m);
  return x;
}

Eigen::VectorXd hertzStiffness(const VehicleModel& model, const Eigen::VectorXd& compression) {
  const double C = model.params().hertz_constant_n_m1_5;
  Eigen::VectorXd k(compression.size());
  for (Eigen::Index i = 0; i < k.size(); ++i) k[i] = 1.5 * C * std::sqrt(std::max(0.0, compression[i]));
  return k;
}

}  // namespace

std::vector<double> linearisedHertzStiffness(const VehicleModel& model) {
  RigidRail rail;
  const auto x = wheelPositions(model, 0.0);
  const StaticState s = staticEquilibrium(model, rail, x, std::vector<double>(x.size(), 0.0));
  const Eigen::VectorXd k = hertzStiffness(model, s.compression_m);
  return std::vector<double>(k.data(), k.data() + k.size());
}

std::vector<Mode> vehicleModesRigid(const VehicleModel& model) {
  const auto kH = linearisedHertzStiffness(model);
  const Eigen::MatrixXd& B = model.contactSelection();
  const Eigen::VectorXd kv = Eigen::Map<const Eigen::VectorXd>(kH.data(), static_cast<Eigen::Index>(kH.size()));
  const Eigen::MatrixXd K = model.stiffness() + B * kv.asDiagonal() * B.transpose();
  std::vector<std::complex<double>> lambdas;
  std::vector<Eigen::VectorXcd> shapes;
  dampedModes(model.mass(), model.damping(), K, lambdas, shapes);
  const DofLabels L = labels(model);
  std::vector<Mode> modes;
  for (size_t k = 0; k < lambdas.size(); ++k) {
    Mode m = modeFrom(lambdas[k]);
    nameMode(model, L, shapes[k], m);
    modes.push_back(m);
  }
  std::sort(modes.begin(), modes.end(), [](const Mode& a, const Mode& b) { return a.frequency_hz < b.frequency_hz; });
  return modes;
}

std::vector<Mode> vehicleModesFlexible(const VehicleModel& model, const track::TrackParams& track_params,
                                       const ModalOptions& opt) {
  const auto x = wheelPositions(model, opt.front_axle_x_m);
  track::TrackParams tp = track_params;
  tp.layout.x_min_m = *std::min_element(x.begin(), x.end()) - opt.margin_m;
  tp.layout.x_max_m = *std::max_element(x.begin(), x.end()) + opt.margin_m;
  tp.ends.absorbing_length_m = 0.0;
  FlexibleRail rail(tp, 1e-5);
  const StaticState s = staticEquilibrium(model, rail, x, std::vector<double>(x.size(), 0.0));
  const Eigen::VectorXd kH = hertzStiffness(model, s.compression_m);
  const track::TrackModel tm(tp);

  const Eigen::Index nv = model.dofCount(), nt = tm.dofCount(), n = nv + nt;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n), C = M, K = M;
  M.topLeftCorner(nv, nv) = model.mass();
  C.topLeftCorner(nv, nv) = model.damping();
  K.topLeftCorner(nv, nv) = model.stiffness();
  M.bottomRightCorner(nt, nt) = Eigen::MatrixXd(tm.mass());
  C.bottomRightCorner(nt, nt) = Eigen::MatrixXd(tm.damping());
  K.bottomRightCorner(nt, nt) = Eigen::MatrixXd(tm.stiffness());
  for (int i = 0; i < model.wheelCount(); ++i) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e[model.wheels()[i].contact_dof] = 1.0;
    const track::RailPoint p = tm.railPoint(x[i]);
    for (int k = 0; k < 4; ++k) e[nv + p.dofs[k]] -= p.weights[k];
    K.noalias() += kH[i] * e * e.transpose();
  }
  // Massless DOFs (Winkler junction nodes): exact static condensation of K,
  // the same transformation applied to C (quasi-static junction).
  std::vector<Eigen::Index> keep, drop;
  for (Eigen::Index i = 0; i < n; ++i) (M.row(i).cwiseAbs().maxCoeff() > 0.0 ? keep : drop).push_back(i);
  const auto na = static_cast<Eigen::Index>(keep.size()), nb = static_cast<Eigen::Index>(drop.size());
  Eigen::MatrixXd Psi = Eigen::MatrixXd::Zero(n, na);
  for (Eigen::Index a = 0; a < na; ++a) Psi(keep[a], a) = 1.0;
  if (nb > 0) {
    Eigen::MatrixXd Kbb(nb, nb), Kba(nb, na);
    for (Eigen::Index i = 0; i < nb; ++i) {
      for (Eigen::Index j = 0; j < nb; ++j) Kbb(i, j) = K(drop[i], drop[j]);
      for (Eigen::Index j = 0; j < na; ++j) Kba(i, j) = K(drop[i], keep[j]);
    }
    const Eigen::MatrixXd X = -Kbb.ldlt().solve(Kba);
    for (Eigen::Index i = 0; i < nb; ++i) Psi.row(drop[i]) = X.row(i);
  }
  const Eigen::MatrixXd Mr = Psi.transpose() * M * Psi, Kr = Psi.transpose() * K * Psi;
  const Eigen::MatrixXd Cr = Psi.transpose() * C * Psi;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(Kr, Mr);
  if (ges.info() != Eigen::Success) throw std::runtime_error("flexible modal analysis: eigen solver failed");
  const double wcut = 2.0 * M_PI * opt.basis_cutoff_hz;
  Eigen::Index m = 0;
  while (m < na && ges.eigenvalues()[m] < wcut * wcut) ++m;
  const Eigen::MatrixXd Phi = Psi * ges.eigenvectors().leftCols(m);  // mass-normalised on Mr
  std::vector<std::complex<double>> lambdas;
  std::vector<Eigen::VectorXcd> shapes;
  dampedModes(Eigen::MatrixXd::Identity(m, m), Phi.transpose() * C * Phi,
              Eigen::MatrixXd(ges.eigenvalues().head(m).asDiagonal()), lambdas, shapes);
  const DofLabels L = labels(model);
  const Eigen::MatrixXcd Mc = M.cast<std::complex<double>>();
  std::vector<Mode> modes;
  for (size_t k = 0; k < lambdas.size(); ++k) {
    const Eigen::VectorXcd xfull = Phi.cast<std::complex<double>>() * shapes[k];
    const double e_total = std::abs(xfull.dot(Mc * xfull));
    const Eigen::VectorXcd xv = xfull.head(nv);
    const double e_vehicle = std::abs(xv.dot(model.mass().cast<std::complex<double>>() * xv));
    Mode md = modeFrom(lambdas[k]);
    md.vehicle_energy_share = e_total > 0.0 ? e_vehicle / e_total : 0.0;
    if (md.vehicle_energy_share < opt.min_vehicle_energy_share) continue;
    nameMode(model, L, xv, md);
    modes.push_back(md);
  }
  std::sort(modes.begin(), modes.end(), [](const Mode& a, const Mode& b) { return a.frequency_hz < b.frequency_hz; });
  return modes;
}

std::vector<std::complex<double>> wheelImpedanceRigid(const VehicleModel& model, int wheel,
                                                      const std::vector<double>& freqs) {
  if (wheel < 0 || wheel >= model.wheelCount()) throw std::out_of_range("wheel index out of range");
  const auto kH = linearisedHertzStiffness(model);
  const Eigen::MatrixXd& B = model.contactSelection();
  const Eigen::VectorXd kv = Eigen::Map<const Eigen::VectorXd>(kH.data(), static_cast<Eigen::Index>(kH.size()));
  const Eigen::MatrixXd K = model.stiffness() + B * kv.asDiagonal() * B.transpose();
  const Eigen::Index c = model.wheels()[wheel].contact_dof;
  std::vector<std::complex<double>> Z;
  for (double f : freqs) {
    const double w = 2.0 * M_PI * f;
    const std::complex<double> iw(0.0, w);
    const Eigen::MatrixXcd D = K.cast<std::complex<double>>() - (w * w) * model.mass().cast<std::complex<double>>() +
                               iw * model.damping().cast<std::complex<double>>();
    Eigen::VectorXcd e = Eigen::VectorXcd::Zero(D.rows());
    e[c] = 1.0;
    const Eigen::VectorXcd u = D.partialPivLu().solve(e);
    Z.push_back(1.0 / (iw * u[c]));
  }
  return Z;
}

std::vector<std::complex<double>> wheelImpedanceFlexible(const VehicleModel& model,
                                                         const track::TrackParams& track_params, int wheel,
                                                         const std::vector<double>& freqs, double front) {
  if (wheel < 0 || wheel >= model.wheelCount()) throw std::out_of_range("wheel index out of range");
  using cd = std::complex<double>;
  const auto x = wheelPositions(model, front);
  FlexibleRail rail(track_params, 1e-5);
  const StaticState s = staticEquilibrium(model, rail, x, std::vector<double>(x.size(), 0.0));
  const Eigen::VectorXd kH = hertzStiffness(model, s.compression_m);
  const track::TrackModel tm(track_params);
  const int nw = model.wheelCount();
  std::vector<track::RailPoint> pts;
  for (double xi : x) pts.push_back(tm.railPoint(xi));
  const Eigen::SparseMatrix<cd> Mt = tm.mass().cast<cd>(), Ct = tm.damping().cast<cd>(), Kt = tm.stiffness().cast<cd>();
  Eigen::SparseLU<Eigen::SparseMatrix<cd>> lu;
  Eigen::SparseMatrix<cd> D = Kt + Mt + Ct;
  lu.analyzePattern(D);
  const Eigen::MatrixXd& B = model.contactSelection();
  const Eigen::Index c = model.wheels()[wheel].contact_dof;
  Eigen::MatrixXcd rhs = Eigen::MatrixXcd::Zero(tm.dofCount(), nw);
  for (int j = 0; j < nw; ++j)
    for (int k = 0; k < 4; ++k) rhs(pts[j].dofs[k], j) += pts[j].weights[k];
  std::vector<cd> Z;
  for (double f : freqs) {
    const double w = 2.0 * M_PI * f;
    const cd iw(0.0, w);
    D = Kt - cd(w * w) * Mt + iw * Ct;
    lu.factorize(D);
    if (lu.info() != Eigen::Success) throw std::runtime_error("wheel impedance: track factorisation failed");
    const Eigen::MatrixXcd X = lu.solve(rhs);
    const Eigen::MatrixXcd Rt = rhs.transpose() * X;  // nw x nw rail receptance (m/N)
    // contact springs in series with the rail: F = (I + kH Rt)^{-1} kH w_wheel
    const Eigen::MatrixXcd Kc = (Eigen::MatrixXcd::Identity(nw, nw) + kH.cast<cd>().asDiagonal() * Rt)
                                    .partialPivLu()
                                    .solve(Eigen::MatrixXcd(kH.cast<cd>().asDiagonal()));
    const Eigen::MatrixXcd Dv = model.stiffness().cast<cd>() - cd(w * w) * model.mass().cast<cd>() +
                                iw * model.damping().cast<cd>() + B.cast<cd>() * Kc * B.transpose().cast<cd>();
    Eigen::VectorXcd e = Eigen::VectorXcd::Zero(Dv.rows());
    e[c] = 1.0;
    const Eigen::VectorXcd u = Dv.partialPivLu().solve(e);
    Z.push_back(1.0 / (iw * u[c]));
  }
  return Z;
}

}  // namespace railvib::vehicle
