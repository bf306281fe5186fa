#include "railvib/vehicle/vehicle_model.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
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
  const int n_spec = static_cast<int>(p.bodies.size());
  const int n_wheel = p.axleCount();
  if (n_spec == 0 || n_wheel == 0) throw std::invalid_argument("VehicleModel: a vehicle needs bodies and wheels");
  const double share = p.body_share_per_rail;
  const bool full = p.fullWidth();
  const double a_rail = p.rail_offset_m;
  if (full && !(a_rail > 0.0)) throw std::invalid_argument("VehicleModel: full width needs the rails' offset > 0");

  // ---- full coordinates: z (and theta, and at full width phi of centre-line bodies) of every
  // body, in file order; at full width a body of one side twice (left, then its mirror image)
  std::vector<double> m;
  auto addDof = [&](const std::string& name, double mass) {
    full_names_.push_back(name);
    m.push_back(mass);
    return static_cast<Eigen::Index>(m.size() - 1);
  };
  // instance[spec][side]: the body of each side (side 0 = left or the centre line, 1 = right)
  std::vector<std::array<int, 2>> instance(static_cast<size_t>(n_spec), {-1, -1});
  int n_carbody = 0, n_bogie = 0;
  for (int sb = 0; sb < n_spec; ++sb) {
    const BodySpec& b = p.bodies[sb];
    const bool mirrored = full && !b.onCentreLine();
    for (int side = 0; side < (mirrored ? 2 : 1); ++side) {
      BodyInfo body{b.name, b.kind, 0, b.x_m, -1, -1, b.front_m, b.rear_m, -1, 0.0};
      if (mirrored) body.name += side == 0 ? "_left" : "_right";
      body.y_m = side == 0 ? b.y_m : -b.y_m;
      body.spec = sb;
      if (b.kind == BodyKind::Carbody) body.index = n_carbody++;
      if (b.kind == BodyKind::Bogie) body.index = n_bogie++;
      const double s = full ? 1.0 : railShare(b.y_m, share);
      body.z_dof = addDof(body.name + ".z", s * b.mass_kg);
      if (b.hasPitch()) body.theta_dof = addDof(body.name + ".theta", s * b.pitch_inertia_kg_m2);
      if (full && b.onCentreLine()) {
        if (!(b.roll_inertia_kg_m2 > 0.0))
          throw std::invalid_argument("VehicleModel: full width: body '" + b.name + "' has no roll inertia");
        body.phi_dof = addDof(body.name + ".phi", b.roll_inertia_kg_m2);
      }
      instance[sb][side] = static_cast<int>(bodies_.size());
      bodies_.push_back(body);
    }
    if (!mirrored) instance[sb][1] = instance[sb][0];
  }
  const Eigen::Index nf = static_cast<Eigen::Index>(m.size());
  m_full_ = Eigen::Map<Eigen::VectorXd>(m.data(), nf);
  total_mass_ = 0.0;
  for (const auto& body : bodies_) total_mass_ += m_full_[body.z_dof];
  const int sides = full ? 2 : 1;

  // ---- mirror image: left and right instances swap, roll changes sign
  mirror_dof_.resize(static_cast<size_t>(nf));
  mirror_sign_ = Eigen::VectorXd::Ones(nf);
  for (Eigen::Index i = 0; i < nf; ++i) mirror_dof_[i] = i;
  for (int sb = 0; sb < n_spec; ++sb) {
    const BodyInfo& l = bodies_[instance[sb][0]];
    const BodyInfo& r = bodies_[instance[sb][1]];
    mirror_dof_[l.z_dof] = r.z_dof;
    mirror_dof_[r.z_dof] = l.z_dof;
    if (l.theta_dof >= 0) {
      mirror_dof_[l.theta_dof] = r.theta_dof;
      mirror_dof_[r.theta_dof] = l.theta_dof;
    }
    if (l.phi_dof >= 0) mirror_sign_[l.phi_dof] = -1.0;
  }

  // ---- wheel parts: the bodies below a bogie (or the carbody) on each wheel's chain of elements
  for (int w = 0; w < n_wheel; ++w) {
    int at = p.wheels[w].body;
    std::vector<int> chain{at};
    int bogie = -1;
    for (int guard = 0; guard < n_spec && bogie < 0; ++guard) {
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
    for (int side = 0; side < sides; ++side) {
      for (int b : chain) {
        bodies_[instance[b][side]].index = w;
        bodies_[instance[b][side]].bogie = bogie >= 0 ? instance[bogie][side] : -1;
      }
    }
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    if (bodies_[b].kind != BodyKind::Bogie) continue;
    bodies_[b].bogie = static_cast<int>(b);
    double lo = 1e300, hi = -1e300;
    for (const WheelSpec& w : p.wheels) {
      if (bodies_[instance[w.body][0]].bogie != static_cast<int>(b) &&
          bodies_[instance[w.body][1]].bogie != static_cast<int>(b))
        continue;
      lo = std::min(lo, p.bodies[w.body].x_m);
      hi = std::max(hi, p.bodies[w.body].x_m);
    }
    bodies_[b].half_wheelbase_m = hi >= lo ? 0.5 * (hi - lo) : 0.0;
  }

  // ---- full matrices
  Eigen::MatrixXd Kf = Eigen::MatrixXd::Zero(nf, nf), Cf = Eigen::MatrixXd::Zero(nf, nf);
  // row vector: downward displacement of the point (s, y) of a body
  auto point = [&](int body, double s, double y) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(nf);
    const BodyInfo& bi = bodies_[body];
    r[bi.z_dof] = 1.0;
    if (bi.theta_dof >= 0) r[bi.theta_dof] = s - bi.offset_m;
    if (bi.phi_dof >= 0) r[bi.phi_dof] = y;
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
  // Elements in file order, then the joints' pitch (and roll) springs. (For the T2000 file this is
  // the assembly order of the earlier hand-written model, so its matrices are bit for bit the same.)
  // At full width an element of one side acts at +y between the left instances (or the centre-line
  // bodies) and at -y between the right ones.
  for (const SuspensionSpec& e : p.suspensions) {
    const double s = full ? 1.0 : railShare(e.y_m, share);
    const double k = s == 1.0 ? e.stiffness_n_m : s * e.stiffness_n_m;
    const double d = s == 1.0 ? e.damping_n_s_m : s * e.damping_n_s_m;
    for (int side = 0; side < (full && e.y_m != 0.0 ? 2 : 1); ++side) {
      const double y = side == 0 ? e.y_m : -e.y_m;
      element(point(instance[e.upper_body][side], e.x_m, y), point(instance[e.lower_body][side], e.x_m, y), k, d);
    }
  }
  for (const JointSpec& j : p.joints) {
    const BodyInfo& a = bodies_[instance[j.body_a][0]];
    const BodyInfo& b = bodies_[instance[j.body_b][0]];
    const double s = full ? 1.0 : railShare(j.y_m, share);
    element(unit(a.theta_dof), unit(b.theta_dof), s * j.pitch_stiffness_n_m_rad, s * j.pitch_damping_n_m_s_rad);
    if (!full) continue;
    if (a.phi_dof < 0 || b.phi_dof < 0 || j.y_m != 0.0)
      throw std::invalid_argument("VehicleModel: full width: joint '" + j.name + "' must pin centre-line bodies");
    if (j.roll_stiffness_n_m_rad > 0.0 || j.roll_damping_n_m_s_rad > 0.0)
      element(unit(a.phi_dof), unit(b.phi_dof), j.roll_stiffness_n_m_rad, j.roll_damping_n_m_s_rad);
  }

  // ---- pin constraints eliminated: the bounce of each joint's second body follows the first
  // body's point at the pin: z_b = w_a(x) - (x - s_b) theta_b, with w_a in reduced coordinates.
  // A pin on the centre line does not involve the roll.
  std::vector<bool> dependent(static_cast<size_t>(nf), false);
  for (const JointSpec& j : p.joints) {
    const BodyInfo& b = bodies_[instance[j.body_b][0]];
    if (dependent[b.z_dof])
      throw std::invalid_argument("VehicleModel: body '" + b.name +
                                  "' follows two pins (closed chains of joints are not supported)");
    dependent[b.z_dof] = true;
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
  // Full width: a centre-line wheel body (a solid wheelset) in the displacements of its contact
  // points, w_left = z + a phi in the slot of z and w_right = z - a phi in that of phi.
  if (full) {
    for (const WheelSpec& w : p.wheels) {
      const BodyInfo& b = bodies_[instance[w.body][0]];
      if (b.phi_dof < 0) continue;
      const Eigen::Index rl = reduced_of[b.z_dof], rr = reduced_of[b.phi_dof];
      T_.row(b.z_dof).setZero();
      T_.row(b.phi_dof).setZero();
      T_(b.z_dof, rl) = T_(b.z_dof, rr) = 0.5;
      T_(b.phi_dof, rl) = 0.5 / a_rail;
      T_(b.phi_dof, rr) = -0.5 / a_rail;
    }
  }
  // mirror image in reduced coordinates: a coordinate's slot mirrors as its full coordinate, but a
  // wheelset's two contact points swap
  reduced_mirror_dof_.assign(static_cast<size_t>(nr), -1);
  reduced_mirror_sign_ = Eigen::VectorXd::Ones(nr);
  for (Eigen::Index i = 0; i < nf; ++i) {
    if (reduced_of[i] < 0) continue;
    reduced_mirror_dof_[reduced_of[i]] = reduced_of[mirror_dof_[i]];
    reduced_mirror_sign_[reduced_of[i]] = mirror_sign_[i];
  }
  if (full) {
    for (const WheelSpec& w : p.wheels) {
      const BodyInfo& b = bodies_[instance[w.body][0]];
      if (b.phi_dof < 0) continue;
      const Eigen::Index rl = reduced_of[b.z_dof], rr = reduced_of[b.phi_dof];
      reduced_mirror_dof_[rl] = rr;
      reduced_mirror_dof_[rr] = rl;
      reduced_mirror_sign_[rl] = reduced_mirror_sign_[rr] = 1.0;
    }
  }
  for (Eigen::Index r = 0; r < nr; ++r) {
    if (reduced_mirror_dof_[r] < 0) throw std::invalid_argument("VehicleModel: a side coordinate has no mirror image");
  }
  std::vector<bool> expressed(static_cast<size_t>(nf), false);
  for (const JointSpec& j : p.joints) {
    const BodyInfo& a = bodies_[instance[j.body_a][0]];
    const BodyInfo& b = bodies_[instance[j.body_b][0]];
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

  B_ = Eigen::MatrixXd::Zero(nr, static_cast<Eigen::Index>(n_wheel * sides));
  for (int a = 0; a < n_wheel; ++a) {
    const WheelSpec& spec = p.wheels[a];
    for (int side = 0; side < sides; ++side) {
      const BodyInfo& body = bodies_[instance[spec.body][side]];
      if (dependent[body.z_dof])
        throw std::invalid_argument("VehicleModel: wheel '" + spec.name + "' on a pinned body");
      WheelInfo w;
      w.axle = a;
      w.type = spec.type;
      w.offset_m = body.offset_m;
      w.radius_m = spec.radius_m;
      w.body = instance[spec.body][side];
      w.bogie = body.bogie >= 0 ? bodies_[body.bogie].index : -1;
      w.rail = side == 0 ? track::Rail::Left : track::Rail::Right;
      w.y_m = side == 0 ? a_rail : -a_rail;
      // a centre-line wheelset: its contact point on this rail (the slot of z or of phi)
      w.contact_dof = reduced_of[side == 1 && body.phi_dof >= 0 ? body.phi_dof : body.z_dof];
      w.contact_mass_kg = body.phi_dof >= 0 ? M_(w.contact_dof, w.contact_dof) : m_full_[body.z_dof];
      const Eigen::Index col = static_cast<Eigen::Index>(wheels_.size());
      B_(w.contact_dof, col) = 1.0;
      wheels_.push_back(w);
    }
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
        for (const Eigen::Index r : {bodies_[b].theta_dof, bodies_[b].phi_dof}) {
          if (r >= 0) e[b] += m_full_[r] * shape[r] * shape[r];
        }
        total += e[b];
      }
      std::ostringstream msg;
      msg << "the vehicle is a mechanism: a motion of";
      for (size_t b = 0; b < bodies_.size(); ++b) {
        if (e[b] > 0.1 * total) msg << " " << bodies_[b].name;
      }
      msg << " stretches no element while the wheels stand on the rail (lowest frequency " << f_lowest
          << " Hz): add a support (a suspension, or a joint's pitch" << (full ? " or roll" : "") << " stiffness)";
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
    pose.roll_rad = b.phi_dof >= 0 ? full[b.phi_dof] : 0.0;
    pose.lateral_m = b.y_m;
    out.push_back(pose);
  }
  return out;
}

int VehicleModel::wheelIndex(int axle, track::Rail rail) const {
  if (axle < 0 || axle >= axleCount()) throw std::out_of_range("VehicleModel: no axle " + std::to_string(axle));
  if (!fullWidth()) {
    if (rail != track::Rail::Left)
      throw std::invalid_argument("VehicleModel: the half vehicle has the left rail's wheels only");
    return axle;
  }
  return 2 * axle + (rail == track::Rail::Right ? 1 : 0);
}

std::vector<track::Rail> VehicleModel::wheelRails() const {
  std::vector<track::Rail> rails;
  for (const auto& w : wheels_) rails.push_back(w.rail);
  return rails;
}

int VehicleModel::partnerWheel(int wheel) const {
  if (wheel < 0 || wheel >= wheelCount()) throw std::out_of_range("VehicleModel: no wheel " + std::to_string(wheel));
  return fullWidth() ? (wheel ^ 1) : -1;
}

std::vector<double> uniformStaticWheelLoadsPerRail(const VehicleModel& model) {
  return std::vector<double>(static_cast<size_t>(model.axleCount()),
                             model.weightPerRail() / static_cast<double>(model.axleCount()));
}

}  // namespace railvib::vehicle
