// Shell element: plate and cantilever frequencies against closed forms, no shear locking.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "railvib/building/modal.hpp"
#include "railvib/building/shell.hpp"

using namespace railvib::building;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A rectangular flat grid of shells in the plane spanned by axes a and b (0 = x, 1 = y, 2 = z),
/// with a DOF filter `fixed(node position, local dof)`; returns the lowest frequencies.
std::vector<double> gridFrequencies(double la, double lb, int na, int nb, int axis_a, int axis_b,
                                    const ShellSection& sec, const std::function<bool(double, double, int)>& fixed,
                                    int count) {
  const int nn = (na + 1) * (nb + 1);
  auto id = [&](int i, int j) { return j * (na + 1) + i; };
  std::vector<Eigen::Vector3d> pos(nn);
  for (int j = 0; j <= nb; ++j)
    for (int i = 0; i <= na; ++i) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      p[axis_a] = la * i / na;
      p[axis_b] = lb * j / nb;
      pos[id(i, j)] = p;
    }
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd m = Eigen::VectorXd::Zero(6 * nn);
  for (int j = 0; j < nb; ++j)
    for (int i = 0; i < na; ++i) {
      const std::array<int, 4> n{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      ShellNodes x{pos[n[0]], pos[n[1]], pos[n[2]], pos[n[3]]};
      const ShellMatrix k = shellStiffness(x, sec);
      const auto areas = shellNodalAreas(x);
      for (int a = 0; a < 4; ++a) {
        for (int d = 0; d < 3; ++d) m[6 * n[a] + d] += sec.density_kg_m3 * sec.thickness_m * areas[a];
        for (int b = 0; b < 4; ++b)
          for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c) trip.emplace_back(6 * n[a] + r, 6 * n[b] + c, k(6 * a + r, 6 * b + c));
      }
    }
  std::vector<int> index(6 * nn, -1);
  int nf = 0;
  for (int q = 0; q < nn; ++q)
    for (int d = 0; d < 6; ++d)
      if (!fixed(pos[q][axis_a], pos[q][axis_b], d)) index[6 * q + d] = nf++;
  std::vector<Eigen::Triplet<double>> tf;
  for (auto& t : trip)
    if (index[t.row()] >= 0 && index[t.col()] >= 0) tf.emplace_back(index[t.row()], index[t.col()], t.value());
  Eigen::SparseMatrix<double> kf(nf, nf);
  kf.setFromTriplets(tf.begin(), tf.end());
  Eigen::VectorXd mf(nf);
  for (int g = 0; g < 6 * nn; ++g)
    if (index[g] >= 0) mf[index[g]] = m[g];
  return lowestFrequencies(kf, mf, count);
}

ShellSection concrete(double t) {
  ShellSection s;
  s.young_modulus_pa = 20e9;
  s.poisson = 20e9 / (2 * 8.3e9) - 1.0;
  s.thickness_m = t;
  s.density_kg_m3 = 2400;
  return s;
}

double ssPlateFrequency(double a, const ShellSection& s) {
  const double d = s.young_modulus_pa * std::pow(s.thickness_m, 3) / (12 * (1 - s.poisson * s.poisson));
  return kPi / 2.0 * (2.0 / (a * a)) * std::sqrt(d / (s.density_kg_m3 * s.thickness_m));
}

// Simply supported square plate in the xy plane: w = 0 on the edges, rotation along the edge fixed
// (Kirchhoff's condition), in-plane DOFs fixed (decoupled).
double ssPlate(double a, double t, int n) {
  const ShellSection s = concrete(t);
  auto fixed = [a](double x, double y, int d) {
    if (d == 0 || d == 1 || d == 5) return true;
    const bool ex = std::abs(x) < 1e-9 || std::abs(x - a) < 1e-9;
    const bool ey = std::abs(y) < 1e-9 || std::abs(y - a) < 1e-9;
    if (d == 2) return ex || ey;
    if (d == 3) return ex;  // rx: slope along an edge x = const
    if (d == 4) return ey;
    return false;
  };
  return gridFrequencies(a, a, n, n, 0, 1, s, fixed, 1)[0];
}

}  // namespace

TEST(Shell, SimplySupportedSquarePlateMatchesKirchhoff) {
  const double a = 7.0, t = 0.20;  // the house's floor: 7 m, 0.20 m concrete
  const double f_exact = ssPlateFrequency(a, concrete(t));
  const double f = ssPlate(a, t, 14);  // 0.5 m elements, the default mesh size
  EXPECT_NEAR(f / f_exact, 1.0, 0.03) << "f = " << f << " Hz, Kirchhoff " << f_exact << " Hz";
  std::printf("[ figures ] SS plate 7 m x 0.20 m, 14x14: %.4f Hz, Kirchhoff %.4f Hz (ratio %.4f)\n", f, f_exact,
              f / f_exact);
}

TEST(Shell, ThinPlateDoesNotLock) {
  // a/t = 1000: a locking element would be orders of magnitude too stiff.
  for (int n : {4, 8, 16}) {
    const double a = 5.0, t = 0.005;
    const double ratio = ssPlate(a, t, n) / ssPlateFrequency(a, concrete(t));
    EXPECT_NEAR(ratio, 1.0, n >= 8 ? 0.03 : 0.08) << "n = " << n;
    std::printf("[ figures ] SS plate a/t = 1000, %dx%d: f/f_Kirchhoff = %.4f\n", n, n, ratio);
  }
}

TEST(Shell, CantileverWallOutOfPlaneMatchesBeamTheory) {
  // Masonry strip 1 m wide, 5 m high, clamped at its foot, in the xz plane (normal y).
  ShellSection s;
  s.young_modulus_pa = 10e9;
  s.poisson = 10e9 / (2 * 4.2e9) - 1.0;
  s.thickness_m = 0.25;
  s.density_kg_m3 = 1800;
  const double b = 1.0, h = 5.0;
  auto fixed = [](double, double z, int) { return std::abs(z) < 1e-9; };
  const auto f = gridFrequencies(b, h, 2, 10, 0, 2, s, fixed, 3);
  const double ei = s.young_modulus_pa * b * std::pow(s.thickness_m, 3) / 12.0;
  const double mu = s.density_kg_m3 * b * s.thickness_m;
  const double f_beam = 1.8751 * 1.8751 / (2 * kPi) * std::sqrt(ei / (mu * std::pow(h, 4)));
  // Between the beam (E) and the plate-strip (E / (1 - nu^2)) stiffness: within 3 %.
  EXPECT_NEAR(f[0] / f_beam, 1.0, 0.03) << f[0] << " vs " << f_beam;
  std::printf("[ figures ] cantilever wall out of plane: %.4f Hz, beam %.4f Hz (ratio %.4f)\n", f[0], f_beam,
              f[0] / f_beam);
}

TEST(Shell, CantileverWallInPlaneMatchesBeamTheory) {
  // In-plane bending of a 0.5 m x 5 m strip (2 elements across): the incompatible modes avoid locking.
  ShellSection s;
  s.young_modulus_pa = 10e9;
  s.poisson = 0.19;
  s.thickness_m = 0.25;
  s.density_kg_m3 = 1800;
  const double b = 0.5, h = 5.0;
  // clamped foot; out-of-plane DOFs (uy, rx, rz... rx and rz are out-of-plane rotations here) removed
  auto fixed = [](double, double z, int d) { return std::abs(z) < 1e-9 || d == 1 || d == 3 || d == 5; };
  const auto f = gridFrequencies(b, h, 2, 10, 0, 2, s, fixed, 2);
  const double ei = s.young_modulus_pa * s.thickness_m * std::pow(b, 3) / 12.0;
  const double mu = s.density_kg_m3 * b * s.thickness_m;
  const double f_beam = 1.8751 * 1.8751 / (2 * kPi) * std::sqrt(ei / (mu * std::pow(h, 4)));
  EXPECT_NEAR(f[0] / f_beam, 1.0, 0.03) << f[0] << " vs " << f_beam;
  std::printf("[ figures ] cantilever wall in plane: %.4f Hz, beam %.4f Hz (ratio %.4f)\n", f[0], f_beam,
              f[0] / f_beam);
}
