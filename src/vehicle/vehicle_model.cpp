#include "railvib/vehicle/vehicle_model.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace railvib::vehicle {

namespace {

/// Share of a body or element carried by the modelled rail: once if it belongs to one side,
/// `share` if it lies on the centre line (it spans both rails).
double railShare(double y_m, double share) { return y_m == 0.0 ? share : 1.0; }

}  // namespace

VehicleModel::VehicleModel(const VehicleParams& p) : params_(p) {
  const int n_body = static_cast<int>(p.bodies.size());
  const int n_wheel = p.axleCount();
  if (n_body == 0 || n_wheel == 0) throw std::invalid_argument("VehicleModel: a vehicle needs bodies and wheels");
  const double share = p.body_share_per_rail;

  // ---- full coordinates: z (and theta) of every body, in file order
  std::vector<double> m;
  auto addDof = [&](const std::string& name, double mass) {
    full_names_.push_back(name);
    m.push_back(mass);
    return static_cast<Eigen::Index>(m.size() - 1);
  };
  int n_carbody = 0, n_bogie = 0;
  for (const BodySpec& b : p.bodies) {
    BodyInfo body{b.name, b.kind, 0, b.x_m, -1, -1, b.front_m, b.rear_m, -1, 0.0};
    if (b.kind == BodyKind::Carbody) body.index = n_carbody++;
    if (b.kind == BodyKind::Bogie) body.index = n_bogie++;
    const double s = railShare(b.y_m, share);
    body.z_dof = addDof(b.name + ".z", s * b.mass_kg);
    if (b.hasPitch()) body.theta_dof = addDof(b.name + ".theta", s * b.pitch_inertia_kg_m2);
    bodies_.push_back(body);
  }
  const Eigen::Index nf = static_cast<Eigen::Index>(m.size());
  m_full_ = Eigen::Map<Eigen::VectorXd>(m.data(), nf);
  total_mass_ = 0.0;
  for (const auto& body : bodies_) total_mass_ += m_full_[body.z_dof];

  // ---- wheel parts: the bodies below a bogie (or the carbody) on each wheel's chain of elements
  for (int w = 0; w < n_wheel; ++w) {
    int at = p.wheels[w].body;
    std::vector<int> chain{at};
    int bogie = -1;
    for (int guard = 0; guard < n_body && bogie < 0; ++guard) {
      int up = -1;
      for (const SuspensionSpec& e : p.suspensions) {
        if (e.lower_body == at) up = e.upper_body;
      }
      if (up < 0) break;
      if (p.bodies[up].hasPitch()) {
        if (p.bodies[up].kind == BodyKind::Bogie) bogie = up;
        break;
      }
      chain.push_back(up);
      at = up;
    }
    for (int b : chain) {
      bodies_[b].index = w;
      bodies_[b].bogie = bogie;
    }
  }
  for (int b = 0; b < n_body; ++b) {
    if (bodies_[b].kind != BodyKind::Bogie) continue;
    bodies_[b].bogie = b;
    double lo = 1e300, hi = -1e300;
    for (const WheelSpec& w : p.wheels) {
      if (bodies_[w.body].bogie != b) continue;
      lo = std::min(lo, p.bodies[w.body].x_m);
      hi = std::max(hi, p.bodies[w.body].x_m);
    }
    bodies_[b].half_wheelbase_m = hi >= lo ? 0.5 * (hi - lo) : 0.0;
  }

  // ---- full matrices
  Eigen::MatrixXd Kf = Eigen::MatrixXd::Zero(nf, nf), Cf = Eigen::MatrixXd::Zero(nf, nf);
  auto point = [&](int body, double s) {  // row vector: downward displacement of body point at offset s
    Eigen::VectorXd r = Eigen::VectorXd::Zero(nf);
    const BodyInfo& bi = bodies_[body];
    r[bi.z_dof] = 1.0;
    if (bi.theta_dof >= 0) r[bi.theta_dof] = s - bi.offset_m;
    return r;
  };
  auto unit = [&](Eigen::Index i) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(nf);
    r[i] = 1.0;
    return r;
  };
  auto element = [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b, double k, double d) {
    const Eigen::VectorXd e = a - b;
    Kf.noalias() += k * e * e.transpose();
    Cf.noalias() += d * e * e.transpose();
  };
  // Elements in file order, then the joints' pitch springs. (For the T2000 file this is the
  // assembly order of the earlier hand-written model, so its matrices are bit for bit the same.)
  for (const SuspensionSpec& e : p.suspensions) {
    const double s = railShare(e.y_m, share);
    const double k = s == 1.0 ? e.stiffness_n_m : s * e.stiffness_n_m;
    const double d = s == 1.0 ? e.damping_n_s_m : s * e.damping_n_s_m;
    element(point(e.upper_body, e.x_m), point(e.lower_body, e.x_m), k, d);
  }
  for (const JointSpec& j : p.joints) {
    const double s = railShare(j.y_m, share);
    element(unit(bodies_[j.body_a].theta_dof), unit(bodies_[j.body_b].theta_dof), s * j.pitch_stiffness_n_m_rad,
            s * j.pitch_damping_n_m_s_rad);
  }

  // ---- pin constraints eliminated: the bounce of each joint's second body follows the first
  // body's point at the pin: z_b = w_a(x) - (x - s_b) theta_b, with w_a in reduced coordinates.
  std::vector<bool> dependent(static_cast<size_t>(nf), false);
  for (const JointSpec& j : p.joints) {
    const Eigen::Index zb = bodies_[j.body_b].z_dof;
    if (dependent[zb])
      throw std::invalid_argument("VehicleModel: body '" + bodies_[j.body_b].name +
                                  "' follows two pins (closed chains of joints are not supported)");
    dependent[zb] = true;
  }
  Eigen::Index nr = 0;
  std::vector<Eigen::Index> reduced_of(static_cast<size_t>(nf), -1);
  for (Eigen::Index i = 0; i < nf; ++i) {
    if (!dependent[i]) reduced_of[i] = nr++;
  }
  T_ = Eigen::MatrixXd::Zero(nf, nr);
  for (Eigen::Index i = 0; i < nf; ++i) {
    if (!dependent[i]) T_(i, reduced_of[i]) = 1.0;
  }
  std::vector<bool> expressed(static_cast<size_t>(nf), false);
  for (const JointSpec& j : p.joints) {
    const BodyInfo& a = bodies_[j.body_a];
    const BodyInfo& b = bodies_[j.body_b];
    if (dependent[a.z_dof] && !expressed[a.z_dof]) {
      throw std::invalid_argument("VehicleModel: joint '" + j.name + "': list the pin that carries body '" + a.name +
                                  "' before this one");
    }
    Eigen::RowVectorXd row = T_.row(a.z_dof);
    if (a.theta_dof >= 0) row += (j.x_m - a.offset_m) * T_.row(a.theta_dof);
    if (b.theta_dof >= 0) row -= (j.x_m - b.offset_m) * T_.row(b.theta_dof);
    T_.row(b.z_dof) = row;
    expressed[b.z_dof] = true;
  }

  const Eigen::MatrixXd Mf = m_full_.asDiagonal();
  M_ = T_.transpose() * Mf * T_;
  K_ = T_.transpose() * Kf * T_;
  C_ = T_.transpose() * Cf * T_;
  Eigen::VectorXd fg_full = Eigen::VectorXd::Zero(nf);
  for (const auto& body : bodies_) fg_full[body.z_dof] = m_full_[body.z_dof] * p.gravity_m_s2;
  fg_ = T_.transpose() * fg_full;

  B_ = Eigen::MatrixXd::Zero(nr, n_wheel);
  for (int a = 0; a < n_wheel; ++a) {
    const WheelSpec& spec = p.wheels[a];
    const BodyInfo& body = bodies_[spec.body];
    if (dependent[body.z_dof]) throw std::invalid_argument("VehicleModel: wheel '" + spec.name + "' on a pinned body");
    WheelInfo w;
    w.axle = a;
    w.type = spec.type;
    w.offset_m = body.offset_m;
    w.radius_m = spec.radius_m;
    w.body = spec.body;
    w.bogie = body.bogie >= 0 ? bodies_[body.bogie].index : -1;
    w.contact_mass_kg = m_full_[body.z_dof];
    w.contact_dof = reduced_of[body.z_dof];
    B_(w.contact_dof, a) = 1.0;
    wheels_.push_back(w);
  }

  // ---- support: with every wheel held by a spring to the rail, no motion may be free of strain
  {
    const Eigen::MatrixXd Ks = K_ + 1.0e9 * B_ * B_.transpose();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Ks, M_, Eigen::ComputeEigenvectors);
    if (es.info() != Eigen::Success) throw std::invalid_argument("VehicleModel: eigen solver failed");
    const double lowest = es.eigenvalues()[0];
    const double f_lowest = std::sqrt(std::max(0.0, lowest)) / (2.0 * M_PI);
    if (f_lowest < 0.05) {
      // name the bodies that move in that mode (kinetic energy share > 10 %)
      const Eigen::VectorXd shape = T_ * es.eigenvectors().col(0);
      double total = 0.0;
      std::vector<double> e(bodies_.size(), 0.0);
      for (size_t b = 0; b < bodies_.size(); ++b) {
        e[b] = m_full_[bodies_[b].z_dof] * shape[bodies_[b].z_dof] * shape[bodies_[b].z_dof];
        if (bodies_[b].theta_dof >= 0) {
          e[b] += m_full_[bodies_[b].theta_dof] * shape[bodies_[b].theta_dof] * shape[bodies_[b].theta_dof];
        }
        total += e[b];
      }
      std::ostringstream msg;
      msg << "the vehicle is a mechanism: a motion of";
      for (size_t b = 0; b < bodies_.size(); ++b) {
        if (e[b] > 0.1 * total) msg << " " << bodies_[b].name;
      }
      msg << " stretches no element while the wheels stand on the rail (lowest frequency " << f_lowest
          << " Hz): add a support (a suspension, or a joint's pitch stiffness)";
      throw std::invalid_argument(msg.str());
    }
  }
}

std::string VehicleModel::bogieLabel(const BodyInfo& body) const {
  if (body.bogie < 0) return "vehicle";
  std::string label = bodies_[body.bogie].name;
  std::replace(label.begin(), label.end(), '_', ' ');
  return label;
}

std::vector<BodyPose> VehicleModel::poses(const Eigen::VectorXd& q) const {
  const Eigen::VectorXd full = T_ * q;
  std::vector<BodyPose> out;
  out.reserve(bodies_.size());
  for (const auto& b : bodies_) {
    BodyPose pose;
    pose.offset_m = b.offset_m;
    pose.vertical_displacement_m = full[b.z_dof];
    pose.pitch_rad = b.theta_dof >= 0 ? full[b.theta_dof] : 0.0;
    out.push_back(pose);
  }
  return out;
}

std::vector<double> uniformStaticWheelLoadsPerRail(const VehicleModel& model) {
  return std::vector<double>(static_cast<size_t>(model.wheelCount()),
                             model.weightPerRail() / static_cast<double>(model.wheelCount()));
}

}  // namespace railvib::vehicle
