// Implicit inclusions (soil/implicit_unit.hpp): the stiffness of a stiff inclusion taken by the
// average-acceleration rule inside the soil's central difference (Hughes & Liu 1978).
//  - an implicit inclusion of the soil's own material is the explicit run to second order in dt
//    (the difference falls 4x when dt halves);
//  - a concrete inclusion does not lower the stable step, and the run stays bounded at the soil's step;
//  - undamped, the scheme conserves E = 1/2 v+ M v+ + 1/2 u_n K u_{n+1} + dt^2/8 v+ K_I v+ exactly (the
//    average-acceleration energy of (M - dt^2/4 K_E, K)), with a rigid body and its modes in the solve;
//  - a very stiff implicit box is the rigid body of the same region and mass.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver.hpp"
#include "soil_test_util.hpp"
#include "test_sampling.hpp"

using namespace railvib::soil;
using railvib::soil::testing::kConcrete;
using railvib::soil::testing::kSoil;
using railvib::soil::testing::maxAbs;
using railvib::test::sampledSteps;

namespace {

// 12 x 12 elements of 0.5 m, 8 levels of 0.5 m.
StructuredMesh boxMesh() {
  std::vector<double> z;
  for (int k = 0; k <= 8; ++k) z.push_back(0.5 * k);
  return buildUniformMesh(12, 12, 0.5, 0.5, z, std::vector<Material>(8, kSoil));
}

SolverOptions closedOptions(double dt_s, double beta_s = 0.0) {
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};
  o.precision = Precision::Double;
  o.threads = 1;
  o.rayleigh_beta_s = beta_s;
  o.dt_s = dt_s;
  return o;
}

InclusionSpec block(const Material& m, bool implicit, double x0 = 2.0, double x1 = 4.0, double y0 = 2.0,
                    double y1 = 4.0, double top = 0.0, double bottom = 1.0) {
  InclusionSpec s;
  s.name = "block";
  s.material = m;
  s.implicit = implicit;
  s.rayleigh_beta_s = implicit ? 0.0 : -1.0;
  s.x_min_m = x0, s.x_max_m = x1, s.y_min_m = y0, s.y_max_m = y1, s.top_m = top, s.bottom_m = bottom;
  return s;
}

StructuredMesh withBlock(const InclusionSpec& spec) {
  StructuredMesh m = boxMesh();
  addInclusions(m, {spec}, 1e-9);
  return m;
}

// A vertical Hann pulse (10 ms) on a surface patch beside the block, for `duration_s`; the vertical
// displacement of every surface node every step.
std::vector<double> surfaceHistory(Solver& s, double duration_s) {
  const StructuredMesh& m = s.mesh();
  ForceChannel ch;
  for (size_t j = 8; j <= 9; ++j) {
    for (size_t i = 8; i <= 9; ++i) {
      ch.nodes.push_back(m.node(i, j, 0));
      ch.components.push_back(2);
      ch.weights.push_back(0.25);
    }
  }
  s.addForceChannel(ch);
  std::vector<double> h;
  while (s.time() < duration_s - 1e-12) {
    const double t = s.time();
    s.setChannelValues({t < 0.01 ? 1.0e5 * (0.5 - 0.5 * std::cos(2.0 * M_PI * t / 0.01)) : 0.0});
    s.step();
    for (size_t j = 0; j <= m.ny; ++j)
      for (size_t i = 0; i <= m.nx; ++i) h.push_back(s.displacement(m.node(i, j, 0), 2));
  }
  return h;
}

double relativeDifference(const std::vector<double>& a, const std::vector<double>& b) {
  return railvib::soil::testing::maxAbsDiff(a, b) / maxAbs(b);
}

}  // namespace

TEST(SoilImplicitInclusion, OwnMaterialIsTheExplicitRunToSecondOrder) {
  double previous = 0.0;
  for (double dt : {4.0e-5, 2.0e-5}) {
    Solver plain(boxMesh(), closedOptions(dt));
    Solver implicit(withBlock(block(kSoil, true)), closedOptions(dt));
    const double d = relativeDifference(surfaceHistory(implicit, 0.03), surfaceHistory(plain, 0.03));
    std::printf("implicit soil block vs explicit, dt %.0e s: max |diff| / peak = %.3e\n", dt, d);
    EXPECT_LT(d, 1e-3);
    EXPECT_GT(d, 0.0);  // it is another scheme on the block
    if (previous > 0.0) {
      const double ratio = previous / d;
      std::printf("  ratio over halving dt: %.2f (second order: 4)\n", ratio);
      EXPECT_GT(ratio, 3.5);
      EXPECT_LT(ratio, 4.5);
    }
    previous = d;
  }
}

TEST(SoilImplicitInclusion, ConcreteKeepsTheSoilsStepAndStaysBounded) {
  const Solver plain(boxMesh(), closedOptions(0.0, 4.0e-4));
  Solver stiff(withBlock(block(kConcrete, true)), closedOptions(0.0, 4.0e-4));
  const Solver explicit_stiff(withBlock(block(kConcrete, false)), closedOptions(0.0, 4.0e-4));
  EXPECT_DOUBLE_EQ(stiff.dtUndamped(), plain.dtUndamped());
  EXPECT_DOUBLE_EQ(stiff.dtDamped(), plain.dtDamped());
  std::printf("stable step: soil %.3e s, concrete explicit %.3e s (%.1f x less), implicit %.3e s\n", plain.dt(),
              explicit_stiff.dt(), plain.dt() / explicit_stiff.dt(), stiff.dt());
  EXPECT_LT(explicit_stiff.dt(), 0.2 * plain.dt());
  // 0.2 s at the soil's step (~2000 steps): bounded, and damped by the soil's Rayleigh term.
  const std::vector<double> h = surfaceHistory(stiff, 0.2);
  const size_t plane = (stiff.mesh().nx + 1) * (stiff.mesh().ny + 1);
  double early = 0.0, late = 0.0;
  for (size_t q = 0; q < h.size(); ++q) {
    (q < h.size() / 4 ? early : late) = std::max(q < h.size() / 4 ? early : late, std::abs(h[q]));
  }
  ASSERT_TRUE(std::isfinite(late));
  EXPECT_GT(early, 0.0);
  EXPECT_LT(late, early);
  EXPECT_EQ(h.size() % plane, 0u);
}

namespace {

// The region of the body in the energy test: the concrete block's top face (a ring would do as well).
RigidBodySpec bodyOnBlock(double damping_ratio) {
  RigidBodySpec spec;
  spec.name = "house";
  spec.x_min_m = 2.0, spec.x_max_m = 4.0, spec.y_min_m = 2.0, spec.y_max_m = 4.0, spec.depth_m = 0.0;
  spec.ring_width_m = 0.5;
  spec.reference_m = {3.0, 3.0, 0.0};
  spec.structure = railvib::soil::testing::twoModeStructure(damping_ratio);
  return spec;
}

// v^T K_I v over the implicit block's elements.
double blockEnergyTerm(const Solver& s, const std::vector<double>& v) {
  const StructuredMesh& m = s.mesh();
  const MeshInclusion& inc = m.inclusions.front();
  double e = 0.0;
  for (size_t k = inc.elements.k0; k < inc.elements.k1; ++k) {
    const auto ke =
        boxElementStiffness(m.hx, m.hy, m.z[k + 1] - m.z[k], inc.material.lambda(), inc.material.shearModulus());
    for (size_t j = inc.elements.j0; j < inc.elements.j1; ++j) {
      for (size_t i = inc.elements.i0; i < inc.elements.i1; ++i) {
        double ve[24];
        for (size_t c = 0; c < 8; ++c) {
          const size_t nd = m.node(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          for (size_t d = 0; d < 3; ++d) ve[3 * c + d] = v[3 * nd + d];
        }
        for (size_t r = 0; r < 24; ++r)
          for (size_t q = 0; q < 24; ++q) e += ve[r] * ke[r * 24 + q] * ve[q];
      }
    }
  }
  return e;
}

std::vector<double> energyHistory(double damping_ratio, int steps, size_t* carried = nullptr,
                                  double block_beta_s = 0.0) {
  InclusionSpec concrete = block(kConcrete, true);
  concrete.rayleigh_beta_s = block_beta_s;
  Solver s(withBlock(concrete), closedOptions(0.0));
  const RigidBodySpec spec = bodyOnBlock(damping_ratio);
  s.attachRigidBody(spec);
  if (carried) *carried = s.rigidBody(0).carried_nodes;
  const StructuredMesh& m = s.mesh();
  // A smooth bump of vertical displacement away from the block.
  for (size_t k = 0; k <= m.nz; ++k) {
    for (size_t j = 0; j <= m.ny; ++j) {
      for (size_t i = 0; i <= m.nx; ++i) {
        const double dx = m.x(i) - 4.5, dy = m.y(j) - 4.5, dz = m.z[k] - 1.5;
        if (m.x(i) <= 4.0 && m.y(j) <= 4.0 && m.z[k] <= 1.0) continue;
        s.setDisplacement(m.node(i, j, k), 2, 1e-4 * std::exp(-(dx * dx + dy * dy + dz * dz)));
      }
    }
  }
  const ReducedStructure& st = spec.structure;
  const size_t n = m.nodeCount();
  std::vector<double> v(3 * n);
  railvib::soil::testing::LeapfrogPotential potential(s, st.circular_frequency_rad_s);
  std::vector<double> history;
  const double dt = s.dt();
  for (int step = 0; step < steps; ++step) {
    s.step();
    const double strain = potential.afterStep(s);
    const RigidBodyState& b = s.rigidBody(0);
    for (size_t nd = 0; nd < n; ++nd)
      for (int c = 0; c < 3; ++c) v[3 * nd + c] = s.velocity(nd, c);
    const Eigen::Matrix<double, 6, 6> mb = st.rigid_mass;
    const double body = 0.5 * b.velocity.dot(mb * b.velocity) + b.modal_velocity.dot(st.participation * b.velocity) +
                        0.5 * b.modal_velocity.squaredNorm();
    history.push_back(s.kineticEnergy() + body + strain + dt * dt / 8.0 * blockEnergyTerm(s, v));
  }
  return history;
}

}  // namespace

TEST(SoilImplicitInclusion, UndampedWithABodyConservesTheSchemesEnergy) {
  size_t carried = 0;
  const std::vector<double> h = energyHistory(0.0, sampledSteps(3000), &carried);
  // The ring: the block's top face (5 x 5 node lines of 0.5 m) less its centre node (one element in).
  EXPECT_EQ(carried, 24u);
  double lo = h.front(), hi = h.front();
  for (double e : h) lo = std::min(lo, e), hi = std::max(hi, e);
  std::printf("energy %.6e J, spread %.2e relative over %zu steps\n", h.front(), (hi - lo) / h.front(), h.size());
  EXPECT_GT(h.front(), 0.0);
  EXPECT_LT((hi - lo) / h.front(), 1e-9);
}

TEST(SoilImplicitInclusion, DampedModesOnlyDissipate) {
  const std::vector<double> h = energyHistory(0.05, sampledSteps(2000));
  for (size_t n = 1; n < h.size(); ++n) ASSERT_LE(h[n], h[n - 1] * (1.0 + 1e-12)) << "step " << n;
  EXPECT_LT(h.back(), 0.999 * h.front());
}

TEST(SoilImplicitInclusion, VeryStiffBlockIsTheRigidBodyOfTheSameMass) {
  // The rigid body: the region's soil nodes carried, plus the mass the block has over them.
  const double dt = 0.0;
  Solver rigid(boxMesh(), closedOptions(dt));
  Material stiff = kConcrete;
  stiff.young_modulus_pa = 2.0e13;  // 1000 x concrete, 3e5 x the soil
  Solver meshed(withBlock(block(stiff, true)), closedOptions(dt));
  ASSERT_DOUBLE_EQ(rigid.dt(), meshed.dt());
  RigidBodySpec body;
  body.x_min_m = 2.0, body.x_max_m = 4.0, body.y_min_m = 2.0, body.y_max_m = 4.0, body.depth_m = 1.0;
  body.reference_m = {3.0, 3.0, 0.0};
  // The block's mass over the soil's, lumped to its element corners as the meshed model lumps it (the
  // carried nodes hold the soil's share in both models).
  const StructuredMesh& g = rigid.mesh();
  const double excess = (kConcrete.density_kg_m3 - kSoil.density_kg_m3) * g.hx * g.hy * 0.5 / 8.0;
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  for (size_t k = 0; k < 2; ++k) {
    for (size_t j = 4; j < 8; ++j) {
      for (size_t i = 4; i < 8; ++i) {
        for (size_t c = 0; c < 8; ++c) {
          const Eigen::Vector3d r(g.x(i + (c & 1)) - 3.0, g.y(j + ((c >> 1) & 1)) - 3.0, g.z[k + ((c >> 2) & 1)]);
          Eigen::Matrix<double, 3, 6> ra;
          ra.leftCols<3>().setIdentity();
          ra.rightCols<3>() << 0.0, r.z(), -r.y(), -r.z(), 0.0, r.x(), r.y(), -r.x(), 0.0;
          m += excess * ra.transpose() * ra;
        }
      }
    }
  }
  body.added_mass = m;
  rigid.attachRigidBody(body);
  const std::vector<double> hr = surfaceHistory(rigid, 0.06), hm = surfaceHistory(meshed, 0.06);
  const double d = relativeDifference(hm, hr);
  std::printf("very stiff implicit block vs rigid body: max |diff| / peak = %.3e\n", d);
  EXPECT_LT(d, 0.02);
}

// The inclusion's own Rayleigh term, integrated in its solve (trapezoidal): the scheme's energy loses
// dt beta vbar^T K_I vbar every step, never gains, at the soil's step.
TEST(SoilImplicitInclusion, OwnRayleighDampingOnlyDissipatesAtTheSoilsStep) {
  const int steps = sampledSteps(3000);
  const std::vector<double> undamped = energyHistory(0.0, steps), damped = energyHistory(0.0, steps, nullptr, 1.0e-4);
  double worst_rise = 0.0;
  for (size_t q = 1; q < damped.size(); ++q) worst_rise = std::max(worst_rise, damped[q] - damped[q - 1]);
  std::printf("own beta 1e-4 s: energy %.6e -> %.6e J (undamped %.6e), largest rise per step %.2e relative\n",
              damped.front(), damped.back(), undamped.back(), worst_rise / damped.front());
  EXPECT_LT(worst_rise, 1e-12 * damped.front());
  EXPECT_LT(damped.back(), damped.front() * (1.0 - 1e-4));
  EXPECT_NEAR(undamped.back(), undamped.front(), 1e-9 * undamped.front());
}
