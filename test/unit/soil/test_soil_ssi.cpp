// Soil-structure interaction against published solutions (docs/soil.md "Soil-structure interaction:
// verification").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "railvib/soil/solver.hpp"

using namespace railvib::soil;

// A quarter model with the symmetry plane x = 0 and the antisymmetry plane y = 0 is the full model under a
// load that is symmetric in x and antisymmetric in y, node for node.
TEST(SoilSsi, AntisymmetryPlaneReproducesTheFullModel) {
  const Material soil{61.0e6, 1876.0, 0.25};
  const size_t n = 6;
  const double h = 0.5;
  std::vector<double> z;
  for (size_t k = 0; k <= n; ++k) z.push_back(h * static_cast<double>(k));
  const std::vector<Material> mats(n, soil);
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};
  o.precision = Precision::Double;
  o.threads = 1;
  Solver full(buildUniformMesh(2 * n, 2 * n, h, h, z, mats, -3.0, -3.0), o);
  o.symmetry_x_min = true;
  o.antisymmetry_y_min = true;
  Solver quarter(buildUniformMesh(n, n, h, h, z, mats), o);
  ASSERT_EQ(full.dt(), quarter.dt());
  // Full: +P down at (+-1, 1), -P at (+-1, -1), and loads on the x = 0 plane; quarter: its share.
  ForceChannel f_full, f_quarter;
  const auto& mf = full.mesh();
  const auto& mq = quarter.mesh();
  for (int sx : {-1, 1}) {
    for (int sy : {-1, 1}) {
      f_full.nodes.push_back(mf.node(n + 2 * sx, n + 2 * sy, 0));
      f_full.components.push_back(2);
      f_full.weights.push_back(sy);
    }
  }
  for (int sy : {-1, 1}) {  // on x = 0: no u_x (symmetry); u_y even and u_d odd in y (antisymmetry)
    f_full.nodes.push_back(mf.node(n, n + 3 * sy, 1));
    f_full.components.push_back(1);
    f_full.weights.push_back(0.2);
    f_full.nodes.push_back(mf.node(n, n + 3 * sy, 2));
    f_full.components.push_back(2);
    f_full.weights.push_back(0.3 * sy);
  }
  f_quarter.nodes = {mq.node(2, 2, 0), mq.node(0, 3, 1), mq.node(0, 3, 2)};
  f_quarter.components = {2, 1, 2};
  f_quarter.weights = {1.0, 0.5 * 0.2, 0.5 * 0.3};  // loads on x = 0 are shared with the mirror half
  full.addForceChannel(f_full);
  quarter.addForceChannel(f_quarter);
  for (int step = 0; step < 150; ++step) {
    const double v = 1.0e4 * std::sin(0.05 * step);
    full.setChannelValues({v});
    quarter.setChannelValues({v});
    full.step();
    quarter.step();
  }
  double peak = 0.0, diff = 0.0;
  for (size_t k = 0; k <= n; ++k) {
    for (size_t j = 0; j <= n; ++j) {
      for (size_t i = 0; i <= n; ++i) {
        for (int c = 0; c < 3; ++c) {
          const double a = full.displacement(mf.node(n + i, n + j, k), c);
          const double b = quarter.displacement(mq.node(i, j, k), c);
          peak = std::max(peak, std::abs(a));
          diff = std::max(diff, std::abs(a - b));
        }
      }
    }
  }
  // The plane y = 0 of the full model indeed has u_x = u_d = 0 (antisymmetry), u_y free.
  EXPECT_LT(std::abs(full.displacement(mf.node(n + 1, n, 1), 2)), 1e-12 * peak);
  EXPECT_LT(std::abs(full.displacement(mf.node(n + 1, n, 1), 0)), 1e-12 * peak);
  EXPECT_GT(std::abs(full.displacement(mf.node(n + 1, n, 1), 1)), 1e-3 * peak);
  EXPECT_GT(peak, 0.0);
  EXPECT_LT(diff, 1e-10 * peak);
}
