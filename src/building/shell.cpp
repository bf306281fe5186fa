#include "railvib/building/shell.hpp"

#include <cmath>
#include <stdexcept>

namespace railvib::building {
namespace {

constexpr double kXi[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kEta[4] = {-1.0, -1.0, 1.0, 1.0};

struct Shape {
  Eigen::Vector4d n;
  Eigen::Vector4d dxi;
  Eigen::Vector4d deta;
};

Shape shape(double xi, double eta) {
  Shape s;
  for (int i = 0; i < 4; ++i) {
    s.n[i] = 0.25 * (1.0 + xi * kXi[i]) * (1.0 + eta * kEta[i]);
    s.dxi[i] = 0.25 * kXi[i] * (1.0 + eta * kEta[i]);
    s.deta[i] = 0.25 * kEta[i] * (1.0 + xi * kXi[i]);
  }
  return s;
}

/// Jacobian [[x,xi  y,xi], [x,eta  y,eta]] of the local 2D geometry.
Eigen::Matrix2d jacobian(const Shape& s, const Eigen::Vector4d& xl, const Eigen::Vector4d& yl) {
  Eigen::Matrix2d j;
  j << s.dxi.dot(xl), s.dxi.dot(yl), s.deta.dot(xl), s.deta.dot(yl);
  return j;
}

struct LocalFrame {
  Eigen::Matrix3d r;  // rows: e1, e2, e3 (local = r * global)
  Eigen::Vector4d xl, yl;
};

LocalFrame localFrame(const ShellNodes& x) {
  const Eigen::Vector3d c = 0.25 * (x[0] + x[1] + x[2] + x[3]);
  Eigen::Vector3d e3 = (x[2] - x[0]).cross(x[3] - x[1]);
  if (e3.norm() <= 0.0) throw std::invalid_argument("shell element: degenerate geometry");
  e3.normalize();
  Eigen::Vector3d e1 = (x[1] - x[0]) - (x[1] - x[0]).dot(e3) * e3;
  e1.normalize();
  const Eigen::Vector3d e2 = e3.cross(e1);
  LocalFrame f;
  f.r.row(0) = e1.transpose();
  f.r.row(1) = e2.transpose();
  f.r.row(2) = e3.transpose();
  for (int i = 0; i < 4; ++i) {
    f.xl[i] = (x[i] - c).dot(e1);
    f.yl[i] = (x[i] - c).dot(e2);
  }
  return f;
}

constexpr double kGauss = 0.57735026918962576451;

}  // namespace

double shellWarp(const ShellNodes& x) {
  const Eigen::Vector3d c = 0.25 * (x[0] + x[1] + x[2] + x[3]);
  const Eigen::Vector3d n = (x[2] - x[0]).cross(x[3] - x[1]).normalized();
  double w = 0.0;
  for (const auto& p : x) w = std::max(w, std::abs((p - c).dot(n)));
  return w / (x[2] - x[0]).norm();
}

std::array<double, 4> shellNodalAreas(const ShellNodes& x) {
  const LocalFrame f = localFrame(x);
  std::array<double, 4> a{0.0, 0.0, 0.0, 0.0};
  for (double xi : {-kGauss, kGauss}) {
    for (double eta : {-kGauss, kGauss}) {
      const Shape s = shape(xi, eta);
      const double det = jacobian(s, f.xl, f.yl).determinant();
      for (int i = 0; i < 4; ++i) a[i] += s.n[i] * det;
    }
  }
  return a;
}

ShellMatrix shellStiffness(const ShellNodes& x, const ShellSection& sec) {
  const LocalFrame f = localFrame(x);
  const double e = sec.young_modulus_pa;
  const double nu = sec.poisson;
  const double t = sec.thickness_m;
  const double g = e / (2.0 * (1.0 + nu));

  Eigen::Matrix3d c;  // plane-stress constitutive matrix (per unit thickness)
  c << 1.0, nu, 0.0, nu, 1.0, 0.0, 0.0, 0.0, 0.5 * (1.0 - nu);
  c *= e / (1.0 - nu * nu);
  const Eigen::Matrix3d dm = c * t;
  const Eigen::Matrix3d db = c * (t * t * t / 12.0);
  const double ds = 5.0 / 6.0 * g * t;

  // ---- membrane (QM6): local dofs u0 v0 u1 v1 ... (8) + 4 incompatible
  Eigen::Matrix<double, 8, 8> kcc = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix<double, 8, 4> kci = Eigen::Matrix<double, 8, 4>::Zero();
  Eigen::Matrix4d kii = Eigen::Matrix4d::Zero();
  // ---- plate: local dofs w0 rx0 ry0 w1 ... (12)
  Eigen::Matrix<double, 12, 12> kp = Eigen::Matrix<double, 12, 12>::Zero();

  const Eigen::Matrix2d j0 = jacobian(shape(0.0, 0.0), f.xl, f.yl);
  const Eigen::Matrix2d j0inv = j0.inverse();
  const double det0 = j0.determinant();
  if (det0 <= 0.0) throw std::invalid_argument("shell element: nodes not in circulation order");

  // Covariant transverse shear strain rows at a point: e_xi (which = 0) or e_eta (which = 1).
  auto covariantShear = [&](double xi, double eta, int which) {
    const Shape s = shape(xi, eta);
    const Eigen::Matrix2d j = jacobian(s, f.xl, f.yl);
    Eigen::Matrix<double, 1, 12> row = Eigen::Matrix<double, 1, 12>::Zero();
    const Eigen::Vector4d& dn = which == 0 ? s.dxi : s.deta;
    const double xd = j(which, 0);
    const double yd = j(which, 1);
    for (int i = 0; i < 4; ++i) {
      row(3 * i) = dn[i];             // dw/dxi
      row(3 * i + 1) = -s.n[i] * yd;  // beta_y = -rx
      row(3 * i + 2) = s.n[i] * xd;   // beta_x = ry
    }
    return row;
  };
  const auto ga = covariantShear(0.0, 1.0, 0);
  const auto gc = covariantShear(0.0, -1.0, 0);
  const auto gb = covariantShear(-1.0, 0.0, 1);
  const auto gd = covariantShear(1.0, 0.0, 1);

  double area = 0.0;
  for (double xi : {-kGauss, kGauss}) {
    for (double eta : {-kGauss, kGauss}) {
      const Shape s = shape(xi, eta);
      const Eigen::Matrix2d j = jacobian(s, f.xl, f.yl);
      const double det = j.determinant();
      if (det <= 0.0) throw std::invalid_argument("shell element: distorted (non-positive Jacobian)");
      area += det;
      const Eigen::Matrix2d jinv = j.inverse();
      Eigen::Vector4d nx, ny;
      for (int i = 0; i < 4; ++i) {
        nx[i] = jinv(0, 0) * s.dxi[i] + jinv(0, 1) * s.deta[i];
        ny[i] = jinv(1, 0) * s.dxi[i] + jinv(1, 1) * s.deta[i];
      }
      // membrane
      Eigen::Matrix<double, 3, 8> bm = Eigen::Matrix<double, 3, 8>::Zero();
      for (int i = 0; i < 4; ++i) {
        bm(0, 2 * i) = nx[i];
        bm(1, 2 * i + 1) = ny[i];
        bm(2, 2 * i) = ny[i];
        bm(2, 2 * i + 1) = nx[i];
      }
      // incompatible modes P1 = 1 - xi^2, P2 = 1 - eta^2, derivatives with the centre Jacobian
      const double scale = det0 / det;
      const Eigen::Vector2d dp1 = j0inv * Eigen::Vector2d(-2.0 * xi, 0.0) * scale;
      const Eigen::Vector2d dp2 = j0inv * Eigen::Vector2d(0.0, -2.0 * eta) * scale;
      Eigen::Matrix<double, 3, 4> bi = Eigen::Matrix<double, 3, 4>::Zero();
      bi(0, 0) = dp1[0];
      bi(2, 0) = dp1[1];
      bi(0, 1) = dp2[0];
      bi(2, 1) = dp2[1];
      bi(1, 2) = dp1[1];
      bi(2, 2) = dp1[0];
      bi(1, 3) = dp2[1];
      bi(2, 3) = dp2[0];
      kcc += bm.transpose() * dm * bm * det;
      kci += bm.transpose() * dm * bi * det;
      kii += bi.transpose() * dm * bi * det;
      // bending: kappa = [d bx/dx, d by/dy, d bx/dy + d by/dx], bx = ry, by = -rx
      Eigen::Matrix<double, 3, 12> bb = Eigen::Matrix<double, 3, 12>::Zero();
      for (int i = 0; i < 4; ++i) {
        bb(0, 3 * i + 2) = nx[i];
        bb(1, 3 * i + 1) = -ny[i];
        bb(2, 3 * i + 2) = ny[i];
        bb(2, 3 * i + 1) = -nx[i];
      }
      kp += bb.transpose() * db * bb * det;
      // MITC4 transverse shear
      Eigen::Matrix<double, 2, 12> ecov;
      ecov.row(0) = 0.5 * (1.0 + eta) * ga + 0.5 * (1.0 - eta) * gc;
      ecov.row(1) = 0.5 * (1.0 + xi) * gd + 0.5 * (1.0 - xi) * gb;
      const Eigen::Matrix<double, 2, 12> bs = jinv * ecov;
      kp += bs.transpose() * ds * bs * det;
    }
  }
  const Eigen::Matrix<double, 8, 8> km = kcc - kci * kii.ldlt().solve(kci.transpose());

  // drilling penalty: rz_i - omega(node i), omega = (dv/dx - du/dy) / 2 of the bilinear field
  Eigen::Matrix<double, 24, 24> kl = Eigen::Matrix<double, 24, 24>::Zero();
  const double kd = sec.drilling_factor * g * t * area / 4.0;
  for (int n = 0; n < 4; ++n) {
    const Shape s = shape(kXi[n], kEta[n]);
    const Eigen::Matrix2d jinv = jacobian(s, f.xl, f.yl).inverse();
    Eigen::Matrix<double, 1, 24> b = Eigen::Matrix<double, 1, 24>::Zero();
    for (int i = 0; i < 4; ++i) {
      const double nxi = jinv(0, 0) * s.dxi[i] + jinv(0, 1) * s.deta[i];
      const double nyi = jinv(1, 0) * s.dxi[i] + jinv(1, 1) * s.deta[i];
      b(6 * i + 0) += 0.5 * nyi;
      b(6 * i + 1) -= 0.5 * nxi;
    }
    b(6 * n + 5) += 1.0;
    kl += kd * b.transpose() * b;
  }
  // scatter membrane and plate into the 24 local dofs (u v w rx ry rz per node)
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int a = 0; a < 2; ++a)
        for (int b2 = 0; b2 < 2; ++b2) kl(6 * i + a, 6 * j + b2) += km(2 * i + a, 2 * j + b2);
      for (int a = 0; a < 3; ++a)
        for (int b2 = 0; b2 < 3; ++b2) kl(6 * i + 2 + a, 6 * j + 2 + b2) += kp(3 * i + a, 3 * j + b2);
    }
  }
  // to global axes
  Eigen::Matrix<double, 24, 24> tr = Eigen::Matrix<double, 24, 24>::Zero();
  for (int k = 0; k < 8; ++k) tr.block<3, 3>(3 * k, 3 * k) = f.r;
  ShellMatrix kg = tr.transpose() * kl * tr;
  return 0.5 * (kg + kg.transpose());
}

}  // namespace railvib::building
