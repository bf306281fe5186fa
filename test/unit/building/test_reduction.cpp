// The house reduced on a rigid foundation (building/reduction.hpp): constraint modes are rigid
// motions, the reduced masses are the model's, and the reduced model on a moving base reproduces
// the full one-way response.
#include <gtest/gtest.h>

#include <cmath>

#include "railvib/building/reduction.hpp"
#include "railvib/building/response.hpp"
#include "railvib/common/config.hpp"

using namespace railvib;
using namespace railvib::building;

namespace {

BuildingModel houseModel(std::vector<std::string> overrides = {}) {
  return BuildingModel(
      loadBuildingParams(Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml", overrides).root()));
}

}  // namespace

TEST(RigidBaseReduction, ConstraintModesAreRigidAndMassesAreTheModels) {
  const BuildingModel model = houseModel();
  const Eigen::Vector3d ref(5.0, 3.5, 0.0);
  const RigidBaseReduction red = reduceOnRigidBase(model, 100.0, ref);
  EXPECT_LT(red.constraint_mode_error, 1e-8);
  // Translational masses: superstructure + foundation = the model's total mass.
  const double total = model.totalMass();
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(red.superstructure_rigid_mass(c, c) + red.foundation_rigid_mass(c, c), total, 1e-9 * total);
  }
  // Modal effective masses sum (over all modes) to at most the superstructure mass, and the
  // modes below 100 Hz hold most of the horizontal mass (building-modes: ~0.9).
  const double free_mass = red.superstructure_rigid_mass(0, 0);
  const double lx = red.participation.col(0).squaredNorm(), lz = red.participation.col(2).squaredNorm();
  EXPECT_LE(lx, free_mass * (1.0 + 1e-9));
  EXPECT_LE(lz, free_mass * (1.0 + 1e-9));
  EXPECT_GT(lx / free_mass, 0.8);
  EXPECT_GT(red.modeCount(), 20);
}

// A vertical half-sine velocity pulse of the whole foundation: the full model (one-way solver) and
// the reduced model (modes up to 100 Hz on the rigid base) give the same response-point velocities.
TEST(RigidBaseReduction, ReducedModelOnMovingBaseMatchesTheFullModel) {
  const BuildingModel model = houseModel({"building.mesh.element_size_m=1.0"});  // fast; same physics
  const Eigen::Vector3d ref(5.0, 3.5, 0.0);
  const RigidBaseReduction red = reduceOnRigidBase(model, 100.0, ref);
  const double dt = 2.5e-4, pulse = 0.04;
  const int n = 2400;  // 0.6 s
  BuildingResponseSolver full(model, dt);
  Eigen::MatrixXd vin = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(full.inputColumns()));
  std::vector<double> base(n + 1, 0.0);
  for (int i = 1; i <= n; ++i) {
    const double t = i * dt;
    // Hann pulse: its spectrum is below ~50 Hz, the band the soil model resolves.
    base[i] = t < pulse ? 0.5 * (1.0 - std::cos(2.0 * M_PI * t / pulse)) * 1e-3 : 0.0;
    for (size_t k = 0; k < full.footprint().size(); ++k) vin(i - 1, static_cast<Eigen::Index>(3 * k + 2)) = base[i];
  }
  const Eigen::MatrixXd out = full.process(0, vin);

  // Reduced: eta'' + 2 z w eta' + w^2 eta = -L_z a_z, Newmark average acceleration on the same steps
  // (base velocity linear over each step, as the full solver's sub-steps).
  const int nm = red.modeCount();
  Eigen::VectorXd eta = Eigen::VectorXd::Zero(nm), etad = eta, etadd = eta;
  double err2 = 0.0, ref2 = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double a_base = (base[i] - base[i - 1]) / dt;
    for (int m = 0; m < nm; ++m) {
      const double w = red.circular_frequency_rad_s[m], z = red.damping_ratio[m];
      const double f = -red.participation(m, 2) * a_base;
      const double keff = w * w + 2.0 * z * w * 2.0 / dt + 4.0 / (dt * dt);
      const double rhs = f + (4.0 / (dt * dt)) * eta[m] + (4.0 / dt) * etad[m] + etadd[m] +
                         2.0 * z * w * ((2.0 / dt) * eta[m] + etad[m]);
      const double e_new = rhs / keff;
      const double a_new = (4.0 / (dt * dt)) * (e_new - eta[m]) - (4.0 / dt) * etad[m] - etadd[m];
      etad[m] += 0.5 * dt * (etadd[m] + a_new);
      etadd[m] = a_new;
      eta[m] = e_new;
    }
    Eigen::Matrix<double, 6, 1> qd = Eigen::Matrix<double, 6, 1>::Zero();
    qd[2] = base[i];
    const Eigen::VectorXd v = reducedResponse(model, red, qd, etad);
    for (Eigen::Index c = 0; c < v.size(); ++c) {
      err2 += (v[c] - out(i - 1, c)) * (v[c] - out(i - 1, c));
      ref2 += out(i - 1, c) * out(i - 1, c);
    }
  }
  const double rel = std::sqrt(err2 / ref2);
  std::printf("reduced (%d modes <= 100 Hz) vs full model: rms difference %.3e of the response\n", nm, rel);
  EXPECT_LT(rel, 0.02);
}

// Two-way: the foundation follows the rigid motion fitted to the footprint receivers. For a rigid
// input (a uniform vertical pulse) that is exactly what the one-way bilinear interpolation gives.
TEST(RigidBaseReduction, TwoWayFoundationFollowsTheRigidFitOfTheFootprint) {
  const BuildingModel one = houseModel({"building.mesh.element_size_m=1.0"});
  const BuildingModel two = houseModel({"building.mesh.element_size_m=1.0", "building.coupling=two_way"});
  const double dt = 1e-3;
  const int n = 300;
  BuildingResponseSolver a(one, dt), b(two, dt);
  Eigen::MatrixXd vin = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(a.inputColumns()));
  for (int i = 0; i < n; ++i) {
    const double t = (i + 1) * dt;
    for (size_t k = 0; k < a.footprint().size(); ++k)
      vin(i, static_cast<Eigen::Index>(3 * k + 2)) = t < 0.02 ? std::sin(M_PI * t / 0.02) * 1e-3 : 0.0;
  }
  const Eigen::MatrixXd va = a.process(0, vin), vb = b.process(0, vin);
  EXPECT_LT((va - vb).norm(), 1e-9 * va.norm());
}
