// railvib/soil: the rigid body unit (rigid_body.hpp): soil nodes carried by a rigid foundation,
// with a Craig-Bampton superstructure, advanced in lockstep with the soil.
#include "railvib/soil/rigid_body.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "rigid_body_unit.hpp"

namespace railvib::soil {

namespace {

// Node index range [lo, hi] of a uniform grid (n + 1 nodes from x0, step h) inside [a, b] (with tolerance).
std::pair<long, long> gridRange(double x0, double h, size_t n, double a, double b, double tol) {
  const long lo = std::max(0L, static_cast<long>(std::ceil((a - tol - x0) / h - 1e-9)));
  const long hi = std::min(static_cast<long>(n), static_cast<long>(std::floor((b + tol - x0) / h + 1e-9)));
  return {lo, hi};
}

// The nearest node lines to a and b.
std::pair<long, long> nearestRange(double x0, double h, size_t n, double a, double b) {
  const long lo = std::clamp(std::lround((a - x0) / h), 0L, static_cast<long>(n));
  const long hi = std::clamp(std::lround((b - x0) / h), 0L, static_cast<long>(n));
  return {lo, hi};
}

}  // namespace

RigidBodyCore::RigidBodyCore(const StructuredMesh& m, const std::vector<double>& mass, const RigidBodySpec& spec,
                             double dt_s, double filter_decay, double beta_s)
    : spec_(spec), dt_(dt_s), e_(filter_decay), beta_(beta_s) {
  if (!(spec.x_max_m > spec.x_min_m) || !(spec.y_max_m > spec.y_min_m) || spec.depth_m < 0.0) {
    throw std::invalid_argument("rigid body '" + spec.name + "': empty region");
  }
  const auto [i0, i1] = spec.snap_to_nearest
                            ? nearestRange(m.x0, m.hx, m.nx, spec.x_min_m, spec.x_max_m)
                            : gridRange(m.x0, m.hx, m.nx, spec.x_min_m, spec.x_max_m, spec.snap_tolerance_m);
  const auto [j0, j1] = spec.snap_to_nearest
                            ? nearestRange(m.y0, m.hy, m.ny, spec.y_min_m, spec.y_max_m)
                            : gridRange(m.y0, m.hy, m.ny, spec.y_min_m, spec.y_max_m, spec.snap_tolerance_m);
  size_t k1 = 0;
  if (spec.snap_to_nearest) {
    for (size_t k = 0; k <= m.nz; ++k) {
      if (std::abs(m.z[k] - spec.depth_m) < std::abs(m.z[k1] - spec.depth_m)) k1 = k;
    }
  } else {
    while (k1 + 1 <= m.nz && m.z[k1 + 1] <= spec.depth_m + spec.snap_tolerance_m) ++k1;
  }
  if (i1 < i0 || j1 < j0 || (i1 == i0 && j1 == j0)) {
    throw std::invalid_argument("rigid body '" + spec.name + "': its region holds no line of soil nodes");
  }
  state_.x_min_m = m.x(static_cast<size_t>(i0));
  state_.x_max_m = m.x(static_cast<size_t>(i1));
  state_.y_min_m = m.y(static_cast<size_t>(j0));
  state_.y_max_m = m.y(static_cast<size_t>(j1));
  state_.depth_m = m.z[k1];
  // A ring: node lines within ring_x / ring_y elements of the region's edge.
  const long ring_x = spec.ring_width_m > 0.0 ? std::max(1L, std::lround(spec.ring_width_m / m.hx)) : 0;
  const long ring_y = spec.ring_width_m > 0.0 ? std::max(1L, std::lround(spec.ring_width_m / m.hy)) : 0;
  auto inRing = [&](long i, long j) {
    if (spec.ring_width_m <= 0.0) return true;
    return i - i0 <= ring_x || i1 - i <= ring_x || j - j0 <= ring_y || j1 - j <= ring_y;
  };
  Eigen::Matrix<double, 6, 6> soil_mass = Eigen::Matrix<double, 6, 6>::Zero();
  for (size_t k = 0; k <= k1; ++k) {
    for (long j = j0; j <= j1; ++j) {
      for (long i = i0; i <= i1; ++i) {
        if (!inRing(i, j)) continue;
        const size_t node = m.node(static_cast<size_t>(i), static_cast<size_t>(j), k);
        const Eigen::Vector3d r =
            Eigen::Vector3d(m.x(static_cast<size_t>(i)), m.y(static_cast<size_t>(j)), m.z[k]) - spec.reference_m;
        nodes_.push_back(node);
        offsets_.push_back(r);
        // R_a = [I, -S(r)] (u_a = u + w x r = u - r x w): R_a^T m R_a.
        Eigen::Matrix<double, 3, 6> ra;
        ra.leftCols<3>().setIdentity();
        ra.rightCols<3>() << 0.0, r.z(), -r.y(), -r.z(), 0.0, r.x(), r.y(), -r.x(), 0.0;
        soil_mass += mass[node] * ra.transpose() * ra;
        state_.carried_soil_mass_kg += mass[node];
      }
    }
  }
  state_.carried_nodes = nodes_.size();

  const ReducedStructure& st = spec.structure;
  const int nm = st.modeCount();
  if (st.participation.rows() != nm || (nm > 0 && st.participation.cols() != 6) || st.damping_ratio.size() != nm) {
    throw std::invalid_argument("rigid body '" + spec.name + "': inconsistent reduced structure");
  }
  const int n = 6 + nm;
  Eigen::MatrixXd mc = Eigen::MatrixXd::Zero(n, n);
  mc.topLeftCorner<6, 6>() = soil_mass + spec.added_mass + st.rigid_mass;
  extra_mass_ = Eigen::MatrixXd::Zero(n, n);
  extra_mass_.topLeftCorner<6, 6>() = spec.added_mass + st.rigid_mass;
  if (nm > 0) {
    mc.bottomLeftCorner(nm, 6) = st.participation;
    mc.topRightCorner(6, nm) = st.participation.transpose();
    mc.bottomRightCorner(nm, nm).setIdentity();
    extra_mass_.bottomLeftCorner(nm, 6) = st.participation;
    extra_mass_.topRightCorner(6, nm) = st.participation.transpose();
    extra_mass_.bottomRightCorner(nm, nm).setIdentity();
  }
  state_.total_mass_kg = mc(0, 0);
  omega2_ = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < nm; ++i) {
    omega2_[6 + i] = st.circular_frequency_rad_s[i] * st.circular_frequency_rad_s[i];
    c[6 + i] = 2.0 * st.damping_ratio[i] * st.circular_frequency_rad_s[i];
  }
  coupled_mass_ = mc;
  damping_ = c;
  // Held rigid DOFs: their rows and columns are dropped (velocity 0).
  for (int i = 0; i < n; ++i) {
    if (i >= 6 || !spec.held[static_cast<size_t>(i)]) active_.push_back(i);
  }
  const int na = static_cast<int>(active_.size());
  Eigen::MatrixXd a(na, na), b(na, na);
  for (int r = 0; r < na; ++r) {
    for (int q = 0; q < na; ++q) {
      const double mrq = mc(active_[r], active_[q]) / dt_s;
      const double crq = r == q ? 0.5 * c[active_[r]] : 0.0;
      a(r, q) = mrq + crq;
      b(r, q) = mrq - crq;
    }
  }
  // Central difference in velocity form: (M/dt + C/2) V+ = (M/dt - C/2) V- + F_n - K X_n.
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
    throw std::invalid_argument("rigid body '" + spec.name + "': mass matrix is not positive definite");
  }
  a_inv_ = ldlt.solve(Eigen::MatrixXd::Identity(na, na));
  a_inv_b_ = a_inv_ * b;
  x_ = Eigen::VectorXd::Zero(n);
  v_ = Eigen::VectorXd::Zero(n);
  vf_ = Eigen::VectorXd::Zero(6);
  force_ = Eigen::VectorXd::Zero(n);
  state_.modal_displacement = Eigen::VectorXd::Zero(nm);
  state_.modal_velocity = Eigen::VectorXd::Zero(nm);
}

void RigidBodyCore::setForce(const Eigen::Matrix<double, 6, 1>& f) { soil_force_ = f; }

const Eigen::VectorXd& RigidBodyCore::stepForce() {
  force_.head<6>() = soil_force_;
  for (int i = 6; i < force_.size(); ++i) force_[i] = -omega2_[i] * x_[i];
  return force_;
}

void RigidBodyCore::advance() {
  const int n = static_cast<int>(x_.size());
  stepForce();
  const int na = static_cast<int>(active_.size());
  Eigen::VectorXd va(na), fa(na);
  for (int r = 0; r < na; ++r) {
    va[r] = v_[active_[r]];
    fa[r] = force_[active_[r]];
  }
  const Eigen::VectorXd vn = a_inv_b_ * va + a_inv_ * fa;
  Eigen::VectorXd v_next = Eigen::VectorXd::Zero(n);
  for (int r = 0; r < na; ++r) v_next[active_[r]] = vn[r];
  commitVelocity(v_next);
}

void RigidBodyCore::commitVelocity(const Eigen::VectorXd& v_next) {
  const int n = static_cast<int>(x_.size());
  v_ = v_next;
  x_ += dt_ * v_;
  vf_ = e_ * vf_ + (1.0 - e_) * v_.head<6>();
  state_.displacement = x_.head<6>();
  state_.velocity = v_.head<6>();
  state_.soil_force = soil_force_;
  const int nm = n - 6;
  state_.modal_displacement = x_.tail(nm);
  state_.modal_velocity = v_.tail(nm);
}

RigidBodyCore::NodeFields RigidBodyCore::nodeFields(size_t a) const {
  NodeFields q;
  q.u = nodeValue(x_.head<6>(), a);
  q.v = nodeValue(v_.head<6>(), a);
  q.w = q.u + beta_ * nodeValue(vf_, a);
  return q;
}

Eigen::Vector3d RigidBodyCore::nodeValue(const Eigen::Matrix<double, 6, 1>& q, size_t a) const {
  return q.head<3>() + q.tail<3>().cross(offsets_[a]);
}

double RigidBodyCore::energy() const {
  // Kinetic energy outside the carried nodes' soil mass (which the soil counts) and the modal strain energy.
  const double kinetic = 0.5 * v_.dot(extra_mass_ * v_);
  double strain = 0.0;
  for (int i = 6; i < x_.size(); ++i) strain += 0.5 * omega2_[i] * x_[i] * x_[i];
  return kinetic + strain;
}

}  // namespace railvib::soil
