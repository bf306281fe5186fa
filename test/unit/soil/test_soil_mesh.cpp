#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "railvib/common/config.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/solver.hpp"

using namespace railvib::soil;

#ifndef RAILVIB_SOURCE_DIR
#define RAILVIB_SOURCE_DIR "."
#endif

TEST(SoilMesh, HarenInterfacesOnElementFacesAndResolution) {
  const auto cfg = railvib::Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml");
  const SoilParams p = loadSoilParams(cfg.root());
  const StructuredMesh m = buildMesh(p.profile, p.mesh);
  // Every layer interface of the config (1.2, 3.0, 4.0, 5.0, 6.0 m) is a node plane.
  double top = 0.0;
  for (size_t l = 0; l + 1 < p.profile.size(); ++l) {
    top += p.profile[l].thickness_m;
    double best = 1e9;
    for (double z : m.z) best = std::min(best, std::abs(z - top));
    EXPECT_LT(best, 1e-12) << "interface at " << top << " m";
  }
  EXPECT_NEAR(m.z.back(), p.mesh.depth_m, 1e-12);
  // Each element level has the material of the layer it lies in, and resolves f_max.
  for (size_t k = 0; k < m.nz; ++k) {
    const double mid = 0.5 * (m.z[k] + m.z[k + 1]);
    double t = 0.0;
    size_t layer = p.profile.size() - 1;
    for (size_t l = 0; l + 1 < p.profile.size(); ++l) {
      if (mid < t + p.profile[l].thickness_m) {
        layer = l;
        break;
      }
      t += p.profile[l].thickness_m;
    }
    const Material& mat = m.levelMaterial(k);
    EXPECT_DOUBLE_EQ(mat.young_modulus_pa, p.profile[layer].material.young_modulus_pa);
    const double hmax = std::max({m.hx, m.hy, m.z[k + 1] - m.z[k]});
    EXPECT_LE(hmax, mat.vs() / (p.mesh.f_max_hz * p.mesh.elements_per_wavelength) * (1 + 1e-9));
  }
}

TEST(SoilMesh, MaterialSpeeds) {
  // nu = 0.25: Vp = sqrt(3) Vs, cR = 0.9194 Vs (classical value).
  Material m{2.5e8, 2000.0, 0.25};
  EXPECT_NEAR(m.vp() / m.vs(), std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(m.vr() / m.vs(), 0.91940, 2e-5);
  // Haren layer 1 (the seed paper, Table 3: Vs ~ 120, Vp ~ 184 m/s); half-space Vs ~ 281, Vp ~ 1430.
  EXPECT_NEAR(Material({61e6, 1876, 0.13}).vs(), 120.0, 0.5);
  EXPECT_NEAR(Material({61e6, 1876, 0.13}).vp(), 184.0, 0.5);
  EXPECT_NEAR(Material({465e6, 1992, 0.48}).vs(), 281.0, 0.5);
  EXPECT_NEAR(Material({465e6, 1992, 0.48}).vp(), 1430.0, 3.0);
}

TEST(SoilMesh, ElementStiffnessRigidModesAndSymmetry) {
  const auto k = boxElementStiffness(0.3, 0.4, 0.7, 2e7, 3e7);
  for (int r = 0; r < 24; ++r) {
    for (int q = 0; q < 24; ++q) EXPECT_NEAR(k[r * 24 + q], k[q * 24 + r], 1e-6 * std::abs(k[r * 24 + r]));
  }
  // Rigid translation and rotation about z produce no force.
  const double xs[2] = {0.0, 0.3}, ys[2] = {0.0, 0.4};
  for (int mode = 0; mode < 4; ++mode) {
    std::vector<double> u(24, 0.0);
    for (int c = 0; c < 8; ++c) {
      if (mode < 3) {
        u[3 * c + mode] = 1.0;
      } else {
        u[3 * c + 0] = -ys[(c >> 1) & 1];
        u[3 * c + 1] = xs[c & 1];
      }
    }
    for (int r = 0; r < 24; ++r) {
      double f = 0.0;
      for (int q = 0; q < 24; ++q) f += k[r * 24 + q] * u[q];
      EXPECT_NEAR(f, 0.0, 1e-6 * std::abs(k[r * 24 + r]));
    }
  }
}

TEST(SoilMesh, GlobalEquilibriumOfInternalForces) {
  // Any displacement field: internal forces sum to zero (translation invariance), both precisions.
  const Material a{61e6, 1876, 0.13}, b{465e6, 1992, 0.48};
  for (Precision pr : {Precision::Float, Precision::Double}) {
    SolverOptions o;
    o.precision = pr;
    Solver s(buildUniformMesh(5, 4, 0.3, 0.3, {0.0, 0.2, 0.5, 1.0}, {a, a, b}), o);
    const size_t n = s.mesh().nodeCount();
    for (size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) s.setDisplacement(i, c, 1e-3 * std::sin(0.7 * i + 1.3 * c));
    }
    std::vector<double> f;
    s.internalForce(f);
    double sum[3] = {0, 0, 0}, mag = 0.0;
    for (size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) {
        sum[c] += f[3 * i + c];
        mag += std::abs(f[3 * i + c]);
      }
    }
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(sum[c]), (pr == Precision::Float ? 1e-5 : 1e-11) * mag);
  }
}

TEST(SoilMesh, StaticSurfaceLoadReactionEqualsApplied) {
  // Fixed base, surface patch load, dynamic relaxation to the static state:
  // the base reaction (internal forces on the fixed nodes) balances the load.
  const Material a{61e6, 1876, 0.13};
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};
  o.fixed_bottom = true;
  o.mass_damping_1_s = 150.0;
  o.precision = Precision::Double;
  Solver s(buildUniformMesh(6, 6, 0.5, 0.5, {0.0, 0.5, 1.0, 1.5}, {a, a, a}), o);
  ForceChannel ch;
  const double total = 1.0e4;
  for (size_t j = 2; j <= 4; ++j) {
    for (size_t i = 2; i <= 4; ++i) {
      ch.nodes.push_back(s.mesh().node(i, j, 0));
      ch.components.push_back(2);
      ch.weights.push_back(1.0 / 9.0);
    }
  }
  s.addForceChannel(ch);
  s.setChannelValues({total});
  s.run(6000);
  std::vector<double> f;
  s.internalForce(f);
  double reaction = 0.0;
  const auto& m = s.mesh();
  for (size_t j = 0; j <= m.ny; ++j) {
    for (size_t i = 0; i <= m.nx; ++i) reaction += f[3 * m.node(i, j, m.nz) + 2];
  }
  // Sum of all nodal -K u is zero; on free nodes K u = load, so on the base -K u sums to the load
  // (the support reaction is the opposite, upward).
  EXPECT_NEAR(reaction, total, 1e-3 * total);
  EXPECT_GT(s.displacement(m.node(3, 3, 0), 2), 0.0);  // moves down under a downward load
}
