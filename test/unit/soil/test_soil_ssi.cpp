// Soil-structure interaction against published solutions (soil/ssi_verification.hpp, docs/soil.md
// "Soil-structure interaction: verification"). Reduced models (coarser meshes, smaller boxes) with the
// tolerances they justify; the full-accuracy figures come from `railvib_tool ssi-bench`.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/ssi_verification.hpp"

using namespace railvib::soil;

namespace {

// Vs = 100 m/s, rho = 2000 kg/m3, nu = 1/3; footing half width B = 1 m.
FootingModelSpec coarseFooting() {
  FootingModelSpec f;
  f.h_m = 0.25;  // 4 elements across the half width
  f.threads = 1;
  return f;
}

}  // namespace

TEST(SoilSsi, PublishedClosedFormsOfASquareFooting) {
  const Material m = coarseFooting().material;
  const double unit = m.shearModulus() / (1.0 - m.poisson_ratio);  // B = 1
  // Square (L = B): Gazetas 2 (0.73 + 1.54) = 4.54, Pais & Kausel 3.1 + 1.6 = 4.7.
  EXPECT_NEAR(gazetasVerticalStiffness(m, 1.0, 1.0) / unit, 4.54, 1e-12);
  EXPECT_NEAR(paisKauselVerticalStiffness(m, 1.0, 1.0) / unit, 4.7, 1e-12);
  // Rocking: Gazetas (4/3)^0.75 x 2.9 = 3.598 and 3 (4/3)^0.75 = 3.722 (the two axes of a square differ by
  // 3 %, the spread of his fits); Pais & Kausel 3.2 + 0.8 = 4.0 = 3.73 + 0.27.
  EXPECT_NEAR(gazetasRockingStiffnessX(m, 1.0, 1.0) / unit, 2.9 * std::pow(4.0 / 3.0, 0.75), 1e-12);
  EXPECT_NEAR(gazetasRockingStiffnessY(m, 1.0, 1.0) / unit, 3.0 * std::pow(4.0 / 3.0, 0.75), 1e-12);
  EXPECT_NEAR(paisKauselRockingStiffnessX(m, 1.0, 1.0) / unit, 4.0, 1e-12);
  EXPECT_NEAR(paisKauselRockingStiffnessY(m, 1.0, 1.0) / unit, 4.0, 1e-12);
  // Dynamic: both tend to the static value; Pais & Kausel's dashpot is rho Vp A for nu = 1/3 (psi = 2).
  EXPECT_NEAR(paisKauselVerticalImpedance(m, 1.0, 1.0, 0.0).stiffness_n_m, paisKauselVerticalStiffness(m, 1.0, 1.0),
              1e-6);
  EXPECT_NEAR(paisKauselVerticalImpedance(m, 1.0, 1.0, 1.0).dashpot_n_s_m, m.density_kg_m3 * m.vp() * 4.0, 1e-6);
  EXPECT_NEAR(gazetasSquareVerticalImpedance(m, 1.0, 0.0).stiffness_n_m, gazetasVerticalStiffness(m, 1.0, 1.0), 1e-6);
  // Lysmer's analog: zeta = 0.425 / sqrt(B_z).
  const double r = 1.0, bz = 4.0;
  const double mass = bz * 4.0 * m.density_kg_m3 * r * r * r / (1.0 - m.poisson_ratio);
  const LysmerAnalog a = lysmerAnalog(m, r, mass);
  EXPECT_NEAR(a.mass_ratio, bz, 1e-12);
  EXPECT_NEAR(a.damping_ratio, 0.425 / std::sqrt(bz), 1e-12);
}

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

// Rocking about a horizontal axis: antisymmetric quarter model, dynamic relaxation. The footing's edge gives
// an error linear in h (measured over 4 to 16 elements across the half width, docs/soil.md): extrapolated from
// 4 and 8 elements; the far boundary's effect from a box sweep with the coarse mesh (it does not depend on h:
// 0.1 % between the two meshes).
TEST(SoilSsi, RockingStaticStiffnessWithinTenPercentOfPaisKausel) {
  FootingModelSpec coarse = coarseFooting(), fine = coarseFooting();
  fine.h_m = 0.125;
  const StaticStiffnessResult boxes = runFootingStatic(coarse, FootingMode::Rocking, {3.0, 4.5, 6.0});
  const StaticStiffnessRun fine_run = runFootingStaticBox(fine, FootingMode::Rocking, 3.0);
  const double k = extrapolateToZeroSize(coarse.h_m, boxes.runs[0].stiffness, fine.h_m, fine_run.stiffness) *
                   boxes.extrapolated / boxes.runs[0].stiffness;
  const Material& m = coarse.material;
  const double pk = paisKauselRockingStiffnessX(m, 1.0, 1.0), gazetas = gazetasRockingStiffnessX(m, 1.0, 1.0);
  std::printf(
      "rocking K / (G B^3 / (1 - nu)): FE %.3f (B/h 4: %.3f, 8: %.3f; box exponent %.2f), Pais & Kausel %.3f "
      "(%+.1f %%), Gazetas %.3f (%+.1f %%)\n",
      k / boxes.unit, boxes.runs[0].stiffness / boxes.unit, fine_run.stiffness / boxes.unit, boxes.exponent,
      pk / boxes.unit, 100.0 * (k / pk - 1.0), gazetas / boxes.unit, 100.0 * (k / gazetas - 1.0));
  // The FE converges from above (a conforming mesh is too stiff) and the far boundary stiffens the box.
  EXPECT_GT(boxes.runs[0].stiffness, fine_run.stiffness);
  EXPECT_LT(boxes.extrapolated, boxes.runs[0].stiffness);
  EXPECT_NEAR(k / pk, 1.0, 0.10);
}

// The footing embedded D = 0.75 B, rigid and as a closed concrete box of implicit inclusions (0.25 m walls and
// slabs, E 20 GPa against the soil's 53 MPa shear modulus, the house's concrete damping) carried at its top face:
// the concrete box is as stiff as the rigid one (within 2 %), and both lie within 10 % of Gazetas' (1991)
// embedded-footing formula, extrapolated as the rocking case above (box sweep 4, 6, 8 m; h 0.25 and 0.125 m).
TEST(SoilSsi, EmbeddedConcreteBoxIsRigidAndWithinTenPercentOfGazetas) {
  double stiffness[2] = {0.0, 0.0};
  for (int meshed = 0; meshed < 2; ++meshed) {
    FootingModelSpec coarse = coarseFooting();
    coarse.embedment_m = 0.75;
    coarse.meshed = meshed == 1;
    coarse.wall_m = 0.25;
    FootingModelSpec fine = coarse;
    fine.h_m = 0.125;
    const StaticStiffnessResult boxes = runFootingStatic(coarse, FootingMode::Vertical, {4.0, 6.0, 8.0});
    const StaticStiffnessRun fine_run = runFootingStaticBox(fine, FootingMode::Vertical, 4.0);
    stiffness[meshed] = extrapolateToZeroSize(coarse.h_m, boxes.runs[0].stiffness, fine.h_m, fine_run.stiffness) *
                        boxes.extrapolated / boxes.runs[0].stiffness;
    const double gazetas = gazetasEmbeddedVerticalStiffness(coarse.material, 1.0, 1.0, 0.75);
    const double pk = paisKauselEmbeddedVerticalStiffness(coarse.material, 1.0, 1.0, 0.75);
    std::printf(
        "embedded %s, D / B 0.75: K_z / (G B / (1 - nu)) FE %.3f, Gazetas %.3f (%+.1f %%), Pais & Kausel %.3f "
        "(%+.1f %%)\n",
        meshed ? "concrete box" : "rigid", stiffness[meshed] / boxes.unit, gazetas / boxes.unit,
        100.0 * (stiffness[meshed] / gazetas - 1.0), pk / boxes.unit, 100.0 * (stiffness[meshed] / pk - 1.0));
    EXPECT_NEAR(stiffness[meshed] / gazetas, 1.0, 0.10);
    // Embedment stiffens: above the surface footing's Gazetas value by more than half his embedment factor.
    const double surface = gazetasVerticalStiffness(coarse.material, 1.0, 1.0);
    EXPECT_GT(stiffness[meshed], surface * (1.0 + 0.5 * (gazetas / surface - 1.0)));
  }
  EXPECT_NEAR(stiffness[1] / stiffness[0], 1.0, 0.02);
}

// Vertical impedance of the massless square footing: Hann-windowed sine wavelet, dashpot box (6 B), K = F / U;
// static stiffness from the low-frequency limit. Both meshes extrapolated to h = 0 (linear).
TEST(SoilSsi, VerticalImpedanceWithinFifteenPercentOfGazetas) {
  ImpedanceSpec spec;
  spec.footing = coarseFooting();
  spec.box_m = 6.0;
  spec.pulse_s = 0.02;  // short: back at rest when the bottom's reflection could return, 0.06 s
  spec.a0 = {0.25, 0.5, 1.0, 1.5, 2.0};
  const ImpedanceResult coarse = runFootingImpedance(spec);
  spec.footing.h_m = 0.125;
  const ImpedanceResult fine = runFootingImpedance(spec);
  EXPECT_LT(fine.end_displacement, 1e-2);  // back at rest before the first reflection could return
  const Material& m = spec.footing.material;
  const double vs = m.vs(), b = 1.0;
  auto toZero = [&](double c, double f) { return extrapolateToZeroSize(0.25, c, 0.125, f); };
  const double ks = toZero(coarse.static_stiffness_n_m, fine.static_stiffness_n_m);
  const double ks_g = gazetasVerticalStiffness(m, b, b), ks_pk = paisKauselVerticalStiffness(m, b, b);
  std::printf("vertical K_s / (G B / (1 - nu)): FE %.3f, Gazetas %.3f, Pais & Kausel %.3f\n",
              ks / coarse.stiffness_unit, ks_g / coarse.stiffness_unit, ks_pk / coarse.stiffness_unit);
  EXPECT_NEAR(ks / ks_g, 1.0, 0.10);
  EXPECT_NEAR(ks / ks_pk, 1.0, 0.10);
  for (size_t i = 1; i < spec.a0.size(); ++i) {
    const double a0 = spec.a0[i];
    const VerticalImpedance fe{toZero(coarse.points[i].fe.stiffness_n_m, fine.points[i].fe.stiffness_n_m),
                               toZero(coarse.points[i].fe.dashpot_n_s_m, fine.points[i].fe.dashpot_n_s_m)};
    const DynamicCoefficients c = dynamicCoefficients(fe, ks, b, vs);
    const DynamicCoefficients g = dynamicCoefficients(gazetasSquareVerticalImpedance(m, b, a0), ks_g, b, vs);
    const DynamicCoefficients pk = dynamicCoefficients(paisKauselVerticalImpedance(m, b, b, a0), ks_pk, b, vs);
    std::printf("a0 %.2f: k FE %.3f Gazetas %.3f P&K %.3f | c FE %.3f Gazetas %.3f P&K %.3f\n", a0, c.k, g.k, pk.k, c.c,
                g.c, pk.c);
    // At a0 = 2 this two-mesh extrapolation (4 and 8 elements across B) is 3 % above the one from 8 and 12
    // (+14.8 % there, docs/soil.md): 15 % + 3 % + a margin.
    EXPECT_NEAR(c.k / g.k, 1.0, a0 < 1.9 ? 0.15 : 0.20) << "a0 " << a0;
    EXPECT_NEAR(c.c / g.c, 1.0, 0.15) << "a0 " << a0;
    // The soil's inertia softens the footing, the radiation stiffens the dashpot: both published trends.
    if (i > 1) {
      EXPECT_LT(c.k, dynamicCoefficients(
                         VerticalImpedance{
                             toZero(coarse.points[i - 1].fe.stiffness_n_m, fine.points[i - 1].fe.stiffness_n_m), 0.0},
                         ks, b, vs)
                         .k);
    }
  }
}

// A rigid block of mass ratio B_z = 2 on the footing: free vertical vibration after a short zero-impulse
// wavelet, against Lysmer's analog with the radius of the same area (B/h = 4: the footing's stiffness is
// 6 % high there, +3 % on the frequency).
TEST(SoilSsi, MassiveBlockFollowsLysmersAnalog) {
  BlockSpec spec;
  spec.footing = coarseFooting();
  spec.box_m = 11.0;  // shear waves reflected by the sides return after 0.2 s, two periods
  spec.mass_ratio = 2.0;
  const BlockResult r = runBlock(spec);
  std::printf("block B_z %.2f: damped %.3f Hz (Lysmer %.3f), resonance %.3f Hz (%.3f), zeta %.4f (%.4f), %d extrema\n",
              r.lysmer.mass_ratio, r.damped_hz, r.lysmer.damped_hz, r.resonance_hz, r.lysmer.resonance_hz,
              r.damping_ratio, r.lysmer.damping_ratio, r.extrema_used);
  EXPECT_GE(r.extrema_used, 3);
  EXPECT_NEAR(r.damped_hz / r.lysmer.damped_hz, 1.0, 0.10);
  EXPECT_NEAR(r.resonance_hz / r.lysmer.resonance_hz, 1.0, 0.10);
  EXPECT_NEAR(r.damping_ratio / r.lysmer.damping_ratio, 1.0, 0.10);
}

// Kinematic interaction: the paper's foundation (10 m x 7 m, embedded 0.85 m, front wall 4 m from the exterior
// rail) as a massless rigid box in the Haren profile, a vertical pulse at the track axis; foundation over free
// field at the foundation's centre per one-third octave band. Reduced model (5 elements per shear wavelength at
// 50 Hz, a 10 m x 20 m x 8 m half box with dashpots only): the full model (`ssi-bench kinematic`, docs/soil.md)
// gives 0.07-0.15 at 31.5-50 Hz and 0.53 at 10 Hz; this one 0.08-0.13 and 0.45.
TEST(SoilSsi, EmbeddedFoundationMovesLessThanTheFreeFieldAt30To50Hz) {
  const auto cfg = railvib::Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml");
  const SoilParams p = loadSoilParams(cfg.root());
  KinematicSpec spec;
  spec.profile = p.profile;
  spec.f_max_hz = 50.0;
  spec.elements_per_wavelength = 5.0;
  spec.solver = p.solver;
  spec.solver.boundary = BoundarySpec{};  // dashpots
  spec.solver.threads = 1;
  spec.x_max_m = 10.0;
  spec.y_min_m = -4.0;
  spec.y_max_m = 16.0;
  spec.depth_m = 8.0;
  spec.duration_s = 0.4;
  const KinematicResult r = runKinematic(spec);
  for (const KinematicBand& b : r.bands) {
    std::printf("%5.1f Hz: foundation / free field %.3f (over the footprint average %.3f)\n", b.nominal_hz,
                b.ratio_centre, b.ratio_footprint);
  }
  std::printf("%zu elements, dt %.3g s, energy in the last 10 %% %.1e / %.1e\n", r.elements, r.dt_s,
              r.tail_energy_free_field, r.tail_energy_foundation);
  ASSERT_EQ(r.bands.size(), 8u);              // 10 ... 50 Hz
  EXPECT_LT(r.tail_energy_free_field, 1e-3);  // the transient is complete
  EXPECT_NEAR(r.depth_m, 0.85, 1e-9);         // a node plane at the embedment depth
  for (const KinematicBand& b : r.bands) {
    if (b.nominal_hz > 30.0) {
      EXPECT_LT(b.ratio_centre, 0.5) << b.nominal_hz << " Hz";
    }
  }
  // Kinematic filtering grows with frequency (the foundation spans more of the wavelength).
  EXPECT_LT(r.bands.back().ratio_centre, 0.5 * r.bands.front().ratio_centre);
  EXPECT_GT(r.bands.front().ratio_centre, 0.2);  // at 10 Hz the foundation still follows the ground
}
