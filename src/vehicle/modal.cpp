#include "railvib/vehicle/modal.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include "railvib/track/dynamic_stiffness_lu.hpp"
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
    const auto& axles = model.params().wheels;  // a wheel part's index is its axle
    const bool motor = b.index < static_cast<int>(axles.size()) && axles[b.index].type == AxleType::Motor;
    switch (b.kind) {
      case BodyKind::Carbody:
        L.category[b.z_dof] = "car-body bounce";
        L.category[b.theta_dof] = "car-body pitch";
        if (b.phi_dof >= 0) L.category[b.phi_dof] = "car-body roll";
        break;
      case BodyKind::Bogie:
        L.category[b.z_dof] = bogie + " bounce";
        L.category[b.theta_dof] = bogie + " pitch";
        if (b.phi_dof >= 0) L.category[b.phi_dof] = bogie + " roll";
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
    // a point body on the centre line (a solid wheelset) rolls at full width
    if (b.phi_dof >= 0 && L.category[b.phi_dof].empty()) L.category[b.phi_dof] = "wheelset roll (" + bogie + ")";
    L.body[b.z_dof] = b.name;
    if (b.theta_dof >= 0) L.body[b.theta_dof] = b.name;
    if (b.phi_dof >= 0) L.body[b.phi_dof] = b.name;
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
  if (model.fullWidth()) {
    // the part of the shape that is the negative of its mirror image: (x - mirror(x)) / 2
    double anti = 0.0;
    for (Eigen::Index i = 0; i < full.size(); ++i) {
      const std::complex<double> xa = 0.5 * (full[i] - model.mirrorSign()[i] * full[model.mirrorDof()[i]]);
      anti += m[i] * std::norm(xa);
    }
    mode.antisymmetric_share = total > 0.0 ? anti / total : 0.0;
    if (mode.antisymmetric_share > 0.5 && mode.name.find(" roll") == std::string::npos) mode.name += ", anti-phase";
  }

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

/// Full width: the chain is its own mirror image, so its motions split exactly into those that are
/// their own mirror image (symmetric: the half vehicle's) and those that are its negative
/// (antisymmetric: roll, the sides in anti-phase). Bases of the two (columns; coordinates as the
/// mirror map's: x'[i] = sign[i] x[mirror[i]]), so that each is solved alone and a mode is one or
/// the other even where a bounce and a roll mode share a frequency.
std::array<Eigen::MatrixXd, 2> mirrorBases(const std::vector<Eigen::Index>& mirror, const Eigen::VectorXd& sign) {
  const auto n = static_cast<Eigen::Index>(mirror.size());
  std::vector<Eigen::VectorXd> sym, anti;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index j = mirror[i];
    if (j < 0 || j >= n || mirror[j] != i || sign[j] != sign[i])
      throw std::logic_error("modal analysis: the mirror map is not an involution");
    if (j < i) continue;
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e[i] = 1.0;
    if (j == i) {
      (sign[i] > 0.0 ? sym : anti).push_back(e);
      continue;
    }
    Eigen::VectorXd f = e;
    e[j] = sign[i];   // x_i = x_j's image: symmetric
    f[j] = -sign[i];  // antisymmetric
    sym.push_back(e);
    anti.push_back(f);
  }
  std::array<Eigen::MatrixXd, 2> out;
  const std::vector<Eigen::VectorXd>* parts[2] = {&sym, &anti};
  for (int b = 0; b < 2; ++b) {
    out[b] = Eigen::MatrixXd(n, static_cast<Eigen::Index>(parts[b]->size()));
    for (size_t c = 0; c < parts[b]->size(); ++c) out[b].col(static_cast<Eigen::Index>(c)) = (*parts[b])[c];
  }
  return out;
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

/// The track must have the vehicle's width (both follow track.width; a programme may not mix them).
void checkWidths(const VehicleModel& model, const track::TrackParams& tp) {
  if (model.fullWidth() != (tp.width == track::TrackWidth::Full)) {
    throw std::invalid_argument(
        "vehicle on a flexible track: the vehicle and the track must have the same width (track.width)");
  }
}

/// Each wheel's contact point on its own rail.
std::vector<track::RailPoint> contactPoints(const VehicleModel& model, const track::TrackModel& tm,
                                            const std::vector<double>& x) {
  std::vector<track::RailPoint> pts;
  for (size_t i = 0; i < x.size(); ++i) pts.push_back(tm.railPoint(x[i], model.wheels()[i].rail));
  return pts;
}

/// Static compliance of the track between the wheels' contact points (m/N): as FlexibleRail's, on
/// each wheel's rail.
Eigen::MatrixXd staticCompliance(const VehicleModel& model, const track::TrackModel& tm, const std::vector<double>& x) {
  const auto n = static_cast<Eigen::Index>(x.size());
  const std::vector<track::RailPoint> pts = contactPoints(model, tm, x);
  Eigen::MatrixXd G(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::VectorXd u = tm.staticDeflection({track::PointLoad{x[j], 1.0, model.wheels()[j].rail}});
    for (Eigen::Index i = 0; i < n; ++i) G(i, j) = pts[i].displacement(u);
  }
  return 0.5 * (G + G.transpose());
}

/// The load pattern of a wheel impedance: +1 on the wheel, +-1 on the other wheel of its axle.
Eigen::VectorXcd wheelLoad(const VehicleModel& model, int wheel, AxleLoading loading) {
  if (wheel < 0 || wheel >= model.wheelCount()) throw std::out_of_range("wheel index out of range");
  Eigen::VectorXcd e = Eigen::VectorXcd::Zero(model.dofCount());
  e[model.wheels()[wheel].contact_dof] = 1.0;
  if (loading == AxleLoading::OneWheel) return e;
  if (!model.fullWidth()) {
    // the half vehicle is the in-phase case itself
    if (loading == AxleLoading::AntiPhase)
      throw std::invalid_argument("wheel impedance: the half vehicle has no anti-phase loading (track.width: full)");
    return e;
  }
  const int other = model.partnerWheel(wheel);
  e[model.wheels()[other].contact_dof] = loading == AxleLoading::InPhase ? 1.0 : -1.0;
  return e;
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
  if (!model.fullWidth()) {
    dampedModes(model.mass(), model.damping(), K, lambdas, shapes);
  } else {
    for (const Eigen::MatrixXd& Q : mirrorBases(model.reducedMirrorDof(), model.reducedMirrorSign())) {
      if (Q.cols() == 0) continue;
      const size_t first = shapes.size();
      dampedModes(Q.transpose() * model.mass() * Q, Q.transpose() * model.damping() * Q, Q.transpose() * K * Q, lambdas,
                  shapes);
      for (size_t k = first; k < shapes.size(); ++k) shapes[k] = Q.cast<std::complex<double>>() * shapes[k];
    }
  }
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
  checkWidths(model, tp);
  const track::TrackModel tm(tp);
  const StaticState s = staticEquilibrium(model, staticCompliance(model, tm, x), std::vector<double>(x.size(), 0.0));
  const Eigen::VectorXd kH = hertzStiffness(model, s.compression_m);
  const std::vector<track::RailPoint> pts = contactPoints(model, tm, x);

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
    const track::RailPoint& p = pts[static_cast<size_t>(i)];
    for (int k = 0; k < 4; ++k) e[nv + p.dofs[k]] -= p.weights[k];
    K.noalias() += kH[i] * e * e.transpose();
  }
  const DofLabels L = labels(model);
  const Eigen::MatrixXcd Mc = M.cast<std::complex<double>>();
  std::vector<Mode> modes;
  // The modes of (M, C, K) in the coordinates x = Q y (Q = identity: all of them).
  auto solve = [&](const Eigen::MatrixXd* Q) {
    const Eigen::MatrixXd Mq = Q ? Eigen::MatrixXd(Q->transpose() * M * *Q) : M;
    const Eigen::MatrixXd Kq = Q ? Eigen::MatrixXd(Q->transpose() * K * *Q) : K;
    const Eigen::Index nq = Mq.rows();
    // Massless DOFs (Winkler junction nodes): exact static condensation of K,
    // the same transformation applied to C (quasi-static junction).
    std::vector<Eigen::Index> keep, drop;
    for (Eigen::Index i = 0; i < nq; ++i) (Mq.row(i).cwiseAbs().maxCoeff() > 0.0 ? keep : drop).push_back(i);
    const auto na = static_cast<Eigen::Index>(keep.size()), nb = static_cast<Eigen::Index>(drop.size());
    Eigen::MatrixXd Psi = Eigen::MatrixXd::Zero(nq, na);
    for (Eigen::Index a = 0; a < na; ++a) Psi(keep[a], a) = 1.0;
    if (nb > 0) {
      Eigen::MatrixXd Kbb(nb, nb), Kba(nb, na);
      for (Eigen::Index i = 0; i < nb; ++i) {
        for (Eigen::Index j = 0; j < nb; ++j) Kbb(i, j) = Kq(drop[i], drop[j]);
        for (Eigen::Index j = 0; j < na; ++j) Kba(i, j) = Kq(drop[i], keep[j]);
      }
      const Eigen::MatrixXd X = -Kbb.ldlt().solve(Kba);
      for (Eigen::Index i = 0; i < nb; ++i) Psi.row(drop[i]) = X.row(i);
    }
    if (Q) Psi = *Q * Psi;  // back to the coupled system's coordinates
    const Eigen::MatrixXd Mr = Psi.transpose() * M * Psi, Kr = Psi.transpose() * K * Psi;
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
  };
  if (!model.fullWidth()) {
    solve(nullptr);
  } else {
    // the coupled chain's mirror image: the vehicle's, and the track's (rails swap, sleepers roll back)
    std::vector<Eigen::Index> mirror(static_cast<size_t>(n), -1);
    Eigen::VectorXd sign = Eigen::VectorXd::Ones(n);
    for (Eigen::Index i = 0; i < nv; ++i) {
      mirror[i] = model.reducedMirrorDof()[i];
      sign[i] = model.reducedMirrorSign()[i];
    }
    auto pair = [&](Eigen::Index a, Eigen::Index b, double sg) {
      if (a < 0 || b < 0) return;
      mirror[nv + a] = nv + b;
      mirror[nv + b] = nv + a;
      sign[nv + a] = sign[nv + b] = sg;
    };
    for (int j = 0; j < tm.railNodeCount(); ++j) {
      pair(tm.railW(j, track::Rail::Left), tm.railW(j, track::Rail::Right), 1.0);
      pair(tm.railTheta(j, track::Rail::Left), tm.railTheta(j, track::Rail::Right), 1.0);
    }
    for (int i = 0; i < tm.sleeperCount(); ++i) {
      pair(tm.sleeperDof(i), tm.sleeperDof(i), 1.0);
      pair(tm.sleeperRollDof(i), tm.sleeperRollDof(i), -1.0);
      pair(tm.baseDof(i, track::Rail::Left), tm.baseDof(i, track::Rail::Right), 1.0);
      pair(tm.padDof(i, track::Rail::Left), tm.padDof(i, track::Rail::Right), 1.0);
      pair(tm.matDof(i, track::Rail::Left), tm.matDof(i, track::Rail::Right), 1.0);
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      if (mirror[i] < 0) throw std::logic_error("flexible modal analysis: a track DOF without mirror image");
    }
    for (const Eigen::MatrixXd& Q : mirrorBases(mirror, sign)) {
      if (Q.cols() > 0) solve(&Q);
    }
  }
  std::sort(modes.begin(), modes.end(), [](const Mode& a, const Mode& b) { return a.frequency_hz < b.frequency_hz; });
  return modes;
}

std::vector<std::complex<double>> wheelImpedanceRigid(const VehicleModel& model, int wheel,
                                                      const std::vector<double>& freqs, AxleLoading loading) {
  const Eigen::VectorXcd load = wheelLoad(model, wheel, loading);
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
    const Eigen::VectorXcd u = D.partialPivLu().solve(load);
    Z.push_back(1.0 / (iw * u[c]));
  }
  return Z;
}

std::vector<std::complex<double>> wheelImpedanceFlexible(const VehicleModel& model,
                                                         const track::TrackParams& track_params, int wheel,
                                                         const std::vector<double>& freqs, double front,
                                                         AxleLoading loading) {
  const Eigen::VectorXcd load = wheelLoad(model, wheel, loading);
  using cd = std::complex<double>;
  checkWidths(model, track_params);
  const auto x = wheelPositions(model, front);
  const track::TrackModel tm(track_params);
  const StaticState s = staticEquilibrium(model, staticCompliance(model, tm, x), std::vector<double>(x.size(), 0.0));
  const Eigen::VectorXd kH = hertzStiffness(model, s.compression_m);
  const int nw = model.wheelCount();
  const std::vector<track::RailPoint> pts = contactPoints(model, tm, x);
  const Eigen::SparseMatrix<cd> Mt = tm.mass().cast<cd>(), Ct = tm.damping().cast<cd>(), Kt = tm.stiffness().cast<cd>();
  track::DynamicStiffnessLu lu;
  Eigen::SparseMatrix<cd> D;
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
    lu.factorize(D, "wheel impedance: the track");
    const Eigen::MatrixXcd X = lu.solve(rhs);
    const Eigen::MatrixXcd Rt = rhs.transpose() * X;  // nw x nw rail receptance (m/N)
    // contact springs in series with the rail: F = (I + kH Rt)^{-1} kH w_wheel
    const Eigen::MatrixXcd Kc = (Eigen::MatrixXcd::Identity(nw, nw) + kH.cast<cd>().asDiagonal() * Rt)
                                    .partialPivLu()
                                    .solve(Eigen::MatrixXcd(kH.cast<cd>().asDiagonal()));
    const Eigen::MatrixXcd Dv = model.stiffness().cast<cd>() - cd(w * w) * model.mass().cast<cd>() +
                                iw * model.damping().cast<cd>() + B.cast<cd>() * Kc * B.transpose().cast<cd>();
    const Eigen::VectorXcd u = Dv.partialPivLu().solve(load);
    Z.push_back(1.0 / (iw * u[c]));
  }
  return Z;
}

}  // namespace railvib::vehicle
