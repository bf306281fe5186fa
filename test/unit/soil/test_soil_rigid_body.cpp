// Rigid bodies carried by soil nodes, with a reduced superstructure (soil/rigid_body.hpp):
// the coupled soil + body + modes system must be a consistent central-difference scheme, so
// it conserves the leapfrog energy exactly without damping and never creates energy with it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "railvib/soil/solver.hpp"
#include "soil_test_util.hpp"
#include "test_sampling.hpp"

using namespace railvib::soil;

namespace {

// A closed box (no dashpots, no Rayleigh damping): nothing leaves it.
Solver closedBox() {
  const Material soil{61.0e6, 1876.0, 0.25};
  std::vector<double> z;
  for (int k = 0; k <= 8; ++k) z.push_back(0.5 * k);
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};
  o.precision = Precision::Double;
  o.threads = 1;
  return Solver(buildUniformMesh(10, 10, 0.5, 0.5, z, std::vector<Material>(8, soil)), o);
}

// An embedded body 2 m x 2 m x 1 m with extra mass and two structural modes.
RigidBodySpec foundation(double damping_ratio) {
  RigidBodySpec spec;
  spec.x_min_m = 1.0;
  spec.x_max_m = 3.0;
  spec.y_min_m = 1.5;
  spec.y_max_m = 3.5;
  spec.depth_m = 1.0;
  spec.reference_m = {2.0, 2.5, 0.0};
  spec.added_mass.diagonal() << 800.0, 800.0, 800.0, 400.0, 400.0, 500.0;
  spec.structure = railvib::soil::testing::twoModeStructure(damping_ratio);
  return spec;
}

// Extra kinetic energy of the body (outside the carried soil nodes) with the half-step velocities.
double bodyKinetic(const RigidBodySpec& spec, const RigidBodyState& s) {
  const ReducedStructure& st = spec.structure;
  const Eigen::Matrix<double, 6, 6> m = spec.added_mass + st.rigid_mass;
  return 0.5 * s.velocity.dot(m * s.velocity) + s.modal_velocity.dot(st.participation * s.velocity) +
         0.5 * s.modal_velocity.squaredNorm();
}

// Leapfrog energy H_n = 1/2 v+ M v+ + 1/2 u_n K u_{n+1} (+ the modes' 1/2 w^2 eta_n eta_{n+1}), conserved
// exactly by the undamped central difference; history over `steps` steps from a strained initial state.
std::vector<double> energyHistory(double damping_ratio, int steps) {
  Solver s = closedBox();
  const RigidBodySpec spec = foundation(damping_ratio);
  s.attachRigidBody(spec);
  const StructuredMesh& m = s.mesh();
  // A smooth bump of vertical displacement beside the body (whose nodes start at rest, rigid).
  for (size_t k = 0; k <= m.nz; ++k) {
    for (size_t j = 0; j <= m.ny; ++j) {
      for (size_t i = 0; i <= m.nx; ++i) {
        const bool carried = m.x(i) >= spec.x_min_m && m.x(i) <= spec.x_max_m && m.y(j) >= spec.y_min_m &&
                             m.y(j) <= spec.y_max_m && m.z[k] <= spec.depth_m;
        if (carried) continue;
        const double dx = m.x(i) - 3.5, dy = m.y(j) - 2.0, dz = m.z[k] - 1.0;
        s.setDisplacement(m.node(i, j, k), 2, 1e-4 * std::exp(-(dx * dx + dy * dy + dz * dz)));
      }
    }
  }
  railvib::soil::testing::LeapfrogPotential potential(s, spec.structure.circular_frequency_rad_s);
  std::vector<double> history;
  for (int step = 0; step < steps; ++step) {
    s.step();
    const double strain = potential.afterStep(s);
    history.push_back(s.kineticEnergy() + bodyKinetic(spec, s.rigidBody(0)) + strain);
  }
  return history;
}

}  // namespace

TEST(SoilRigidBody, CarriesTheNodesOfItsRegionWithTheirMass) {
  Solver s = closedBox();
  s.attachRigidBody(foundation(0.0));
  const RigidBodyState& b = s.rigidBody(0);
  // 5 x 5 nodes in plan (x 1..3, y 1.5..3.5 at 0.5 m), 3 node planes (d = 0, 0.5, 1.0).
  EXPECT_EQ(b.carried_nodes, 75u);
  double mass = 0.0;
  for (size_t k = 0; k <= 2; ++k)
    for (size_t j = 3; j <= 7; ++j)
      for (size_t i = 2; i <= 6; ++i) mass += s.nodalMass(s.mesh().node(i, j, k));
  EXPECT_NEAR(b.carried_soil_mass_kg, mass, 1e-9 * mass);
  EXPECT_NEAR(b.total_mass_kg, mass + 800.0 + 3000.0, 1e-9 * mass);
  EXPECT_DOUBLE_EQ(b.depth_m, 1.0);
}

TEST(SoilRigidBody, UndampedCoupledSystemConservesTheLeapfrogEnergy) {
  const std::vector<double> h = energyHistory(0.0, 3000);
  double lo = h.front(), hi = h.front();
  for (double e : h) {
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  std::printf("leapfrog energy %.6e J, spread %.2e relative over %zu steps\n", h.front(), (hi - lo) / h.front(),
              h.size());
  EXPECT_GT(h.front(), 0.0);
  EXPECT_LT((hi - lo) / h.front(), 1e-9);  // exact up to double round-off
}

TEST(SoilRigidBody, DampedModesOnlyDissipate) {
  const std::vector<double> h = energyHistory(0.05, railvib::test::sampledSteps(3000));
  for (size_t n = 1; n < h.size(); ++n) ASSERT_LE(h[n], h[n - 1] * (1.0 + 1e-12)) << "step " << n;
  EXPECT_LT(h.back(), 0.999 * h.front());  // and the structure really takes energy out
}
