#include "railvib/vehicle/vehicle_model.hpp"

#include <stdexcept>

namespace railvib::vehicle {

namespace {
const char* kCarNames[3] = {"front_carbody", "central_carbody", "rear_carbody"};
const char* kBogieNames[3] = {"leading_bogie", "middle_bogie", "rear_bogie"};
}  // namespace

VehicleModel::VehicleModel(const VehicleParams& p) : params_(p) {
  const int n_axle = p.axleCount();
  if (n_axle != 6 || static_cast<int>(p.axle_types.size()) != n_axle) {
    throw std::invalid_argument("VehicleModel: the T2000 model needs 6 axles (3 bogies of 2) with one type each");
  }
  const double share = p.body_share_per_rail;
  const double s_car[3] = {p.carbody_com_offsets_m[0], p.carbody_com_offsets_m[1], p.carbody_com_offsets_m[2]};
  double s_bogie[3];
  for (int b = 0; b < 3; ++b) s_bogie[b] = 0.5 * (p.axle_offsets_m[2 * b] + p.axle_offsets_m[2 * b + 1]);

  // ---- full coordinates
  std::vector<double> m;
  auto addDof = [&](const std::string& name, double mass) {
    full_names_.push_back(name);
    m.push_back(mass);
    return static_cast<Eigen::Index>(m.size() - 1);
  };
  for (int c = 0; c < 3; ++c) {
    const bool central = c == 1;
    BodyInfo body{kCarNames[c], BodyKind::Carbody, c, s_car[c], -1, -1};
    body.z_dof =
        addDof(std::string(kCarNames[c]) + ".z", share * (central ? p.central_carbody_mass_kg : p.end_carbody_mass_kg));
    body.theta_dof =
        addDof(std::string(kCarNames[c]) + ".theta",
               share * (central ? p.central_carbody_pitch_inertia_kg_m2 : p.end_carbody_pitch_inertia_kg_m2));
    bodies_.push_back(body);
  }
  for (int b = 0; b < 3; ++b) {
    BodyInfo body{kBogieNames[b], BodyKind::Bogie, b, s_bogie[b], -1, -1};
    body.z_dof = addDof(std::string(kBogieNames[b]) + ".z", share * p.bogie_mass_kg);
    body.theta_dof = addDof(std::string(kBogieNames[b]) + ".theta", share * p.bogie_pitch_inertia_kg_m2);
    bodies_.push_back(body);
  }
  std::vector<Eigen::Index> motor_dof(n_axle, -1), contact_full(n_axle, -1);
  for (int a = 0; a < n_axle; ++a) {
    const std::string base = "axle" + std::to_string(a);
    if (p.axle_types[a] == AxleType::Motor) {
      motor_dof[a] = addDof(base + "_motor_wheel.z", p.motor_mass_kg);
      bodies_.push_back({base + "_motor_wheel", BodyKind::MotorWheel, a, p.axle_offsets_m[a], motor_dof[a], -1});
      contact_full[a] = addDof(base + "_tread.z", p.tread_mass_kg);
      bodies_.push_back({base + "_tread", BodyKind::Tread, a, p.axle_offsets_m[a], contact_full[a], -1});
    } else {
      contact_full[a] = addDof(base + "_trailer_wheel.z", p.trailer_mass_kg);
      bodies_.push_back({base + "_trailer_wheel", BodyKind::TrailerWheel, a, p.axle_offsets_m[a], contact_full[a], -1});
    }
  }
  const Eigen::Index nf = static_cast<Eigen::Index>(m.size());
  m_full_ = Eigen::Map<Eigen::VectorXd>(m.data(), nf);
  total_mass_ = 0.0;
  for (const auto& body : bodies_) total_mass_ += m_full_[body.z_dof];

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
  // secondary suspension: bogie b centre to carbody b at the same offset
  for (int b = 0; b < 3; ++b) {
    element(point(3 + b, s_bogie[b]), point(b, s_bogie[b]), p.secondary_stiffness_n_m, p.secondary_damping_n_s_m);
  }
  // articulation pitch spring/damper (relative pitch)
  for (int j = 0; j < 2; ++j) {
    element(unit(bodies_[j].theta_dof), unit(bodies_[j + 1].theta_dof), share * p.articulation_pitch_stiffness_n_m_rad,
            share * p.articulation_pitch_damping_n_m_s_rad);
  }
  // primary suspension and resilient ring
  for (int a = 0; a < n_axle; ++a) {
    const int b = a / 2;
    const Eigen::VectorXd on_bogie = point(3 + b, p.axle_offsets_m[a]);
    if (p.axle_types[a] == AxleType::Motor) {
      element(on_bogie, unit(motor_dof[a]), p.motor_primary_stiffness_n_m, p.motor_primary_damping_n_s_m);
      element(unit(motor_dof[a]), unit(contact_full[a]), p.ring_stiffness_n_m, p.ring_damping_n_s_m);
    } else {
      element(on_bogie, unit(contact_full[a]), p.trailer_primary_stiffness_n_m, p.trailer_primary_damping_n_s_m);
    }
  }

  // ---- pin constraints eliminated: reduced coords (z0, th0, th1, th2, rest)
  const Eigen::Index nr = nf - 2;
  T_ = Eigen::MatrixXd::Zero(nf, nr);
  const double a0 = p.articulation_offsets_m[0], a1 = p.articulation_offsets_m[1];
  T_(0, 0) = 1.0;  // z0
  T_(1, 1) = 1.0;  // th0
  T_(3, 2) = 1.0;  // th1
  T_(5, 3) = 1.0;  // th2
  // z1 = z0 + (a0 - c0) th0 - (a0 - c1) th1
  T_(2, 0) = 1.0;
  T_(2, 1) = a0 - s_car[0];
  T_(2, 2) = -(a0 - s_car[1]);
  // z2 = z1 + (a1 - c1) th1 - (a1 - c2) th2
  T_.row(4) = T_.row(2);
  T_(4, 2) += a1 - s_car[1];
  T_(4, 3) += -(a1 - s_car[2]);
  for (Eigen::Index i = 6; i < nf; ++i) T_(i, i - 2) = 1.0;

  const Eigen::MatrixXd Mf = m_full_.asDiagonal();
  M_ = T_.transpose() * Mf * T_;
  K_ = T_.transpose() * Kf * T_;
  C_ = T_.transpose() * Cf * T_;
  Eigen::VectorXd fg_full = Eigen::VectorXd::Zero(nf);
  for (const auto& body : bodies_) fg_full[body.z_dof] = m_full_[body.z_dof] * p.gravity_m_s2;
  fg_ = T_.transpose() * fg_full;

  B_ = Eigen::MatrixXd::Zero(nr, n_axle);
  for (int a = 0; a < n_axle; ++a) {
    WheelInfo w;
    w.axle = a;
    w.type = p.axle_types[a];
    w.offset_m = p.axle_offsets_m[a];
    w.radius_m = w.type == AxleType::Motor ? p.motor_radius_m : p.trailer_radius_m;
    w.bogie = a / 2;
    w.contact_mass_kg = m_full_[contact_full[a]];
    w.contact_dof = contact_full[a] - 2;
    B_(w.contact_dof, a) = 1.0;
    wheels_.push_back(w);
  }
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

}  // namespace railvib::vehicle
