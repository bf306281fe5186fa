// The soil's compliance between sleeper footprints (soil/footprint_compliance.hpp): one impulse run,
// Fourier sums at any frequency. Held against Lamb's problem: on a homogeneous half-space, a small
// footprint a few metres from the loaded one moves as under a point load (Pekeris), whose frequency
// response is the Fourier transform of its Hann pulse response over the pulse's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/soil/footprint.hpp"
#include "railvib/soil/footprint_compliance.hpp"
#include "railvib/soil/lamb.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/ssi_verification.hpp"
#include "soil_test_util.hpp"

using namespace railvib::soil;
using railvib::soil::testing::kSoil;
using railvib::soil::testing::paramsOf;

namespace {

// A homogeneous half-space under a PML on every face but the surface, 0.25 m elements, small
// footprints (0.3 m across the track, 0.25 m along it) every 0.72 m.
std::string homogeneousScenario(double x_half_m, const std::string& boundary = "pml") {
  const std::string mat = "young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, poisson_ratio: 0.25";
  const std::string x = std::to_string(x_half_m);
  return "soil:\n"
         "  layers:\n"
         "    - {thickness_m: 1.0, " +
         mat +
         "}\n"
         "  half_space: {" +
         mat +
         "}\n"
         "  rayleigh_beta_s: 1.0e-5\n"
         "  mesh: {f_max_hz: 20.0, elements_per_wavelength: 8.0, max_plane_size_m: 0.25, x_min_m: -" +
         x + ", x_max_m: " + x +
         ", y_min_m: -3.5, y_max_m: 3.5, depth_m: 6.0}\n"
         "  boundary: {method: " +
         boundary +
         ", pml: {thickness_m: 2.0, reflection_coefficient: 1.0e-3, exponent: 2.0, alpha_1_s: 30.0, max_kappa: 1.0,"
         " perpendicular_ratio: 0.0, bottom: true, outer_dashpots: true}}\n"
         "  loads: {outside_mesh: drop, drop_min_receiver_distance_m: 0.0}\n"
         "  output: {receiver_rate_hz: 1000.0, snapshot_rate_hz: 100.0}\n"
         "track:\n"
         "  sleeper: {spacing_m: 0.72, length_m: 0.3, width_m: 0.25}\n"
         "  extent: {mode: fixed, x_min_m: -5.0, x_max_m: 5.0}\n"
         "  output: {load_sample_rate_hz: 2000.0}\n"
         "site:\n"
         "  rail_gauge_m: 1.435\n"
         "  ground_sensors: [{name: s, x_m: 0.0, y_m: 1.0}]\n"
         "simulation: {duration_s: 0.1}\n";
}

// Pekeris: surface displacement at r per unit point force, in the frequency domain, from the Hann
// pulse response sampled like the FE run (same pulse, same Fourier sums).
std::complex<double> pekerisCompliance(double r_m, double f_hz, double pulse_s, double duration_s, double dt_s) {
  const PekerisSolution p(kSoil);
  std::vector<double> t;
  for (double v = 0.0; v <= duration_s; v += dt_s) t.push_back(v);
  const std::vector<double> w = p.hannPulseResponse(1.0, r_m, pulse_s, t);
  std::complex<double> u = 0.0, f = 0.0;
  for (size_t n = 0; n < t.size(); ++n) {
    const std::complex<double> ph = std::polar(1.0, -2.0 * M_PI * f_hz * t[n]);
    u += w[n] * ph;
    f += hannPulse(t[n], pulse_s) * ph;
  }
  return u / f;
}

}  // namespace

// The footprints 3-5 sleepers away (2.2-3.6 m, 8-13 footprint sizes) against the point-load
// half-space over 4-16 Hz: within 5 % in magnitude and 3 degrees in phase (measured 1.6 %, 0.55 deg; the mesh resolves
// 20 Hz with 8 elements per shear wavelength; the Lamb check of the solver, test_soil_lamb, holds its
// peaks to 10 %). The two sides agree to round-off on this symmetric grid.
TEST(FootprintCompliance, FarFootprintsMoveAsUnderAPointLoadOnAHalfSpace) {
  FootprintComplianceSpec spec;
  spec.pulse_s = 0.03;
  spec.duration_s = 0.6;
  const FootprintCompliance c(paramsOf(homogeneousScenario(6.0)), spec);
  ASSERT_GE(c.distanceCount(), 6u);
  EXPECT_NEAR(c.loadedX(), 0.0, 1e-12);
  const double side_difference = c.summary()["side_difference"];
  EXPECT_LT(side_difference, 1e-4);
  double worst_magnitude = 0.0, worst_phase_deg = 0.0;
  for (size_t k = 3; k <= 5; ++k) {
    for (double f : {4.0, 8.0, 12.0, 16.0}) {
      const std::complex<double> fe = c.compliance(k, f);
      const std::complex<double> an =
          pekerisCompliance(0.72 * static_cast<double>(k), f, spec.pulse_s, spec.duration_s, c.dt());
      EXPECT_NEAR(std::abs(fe) / std::abs(an), 1.0, 0.05) << "k = " << k << ", " << f << " Hz";
      EXPECT_NEAR(std::arg(fe / an) * 180.0 / M_PI, 0.0, 3.0) << "k = " << k << ", " << f << " Hz";
      worst_magnitude = std::max(worst_magnitude, std::abs(std::abs(fe) / std::abs(an) - 1.0));
      worst_phase_deg = std::max(worst_phase_deg, std::abs(std::arg(fe / an)) * 180.0 / M_PI);
    }
  }
  std::printf("footprints 2.2-3.6 m from the load, 4-16 Hz: |FE| / |Pekeris| - 1 at most %.3f, phase %.2f deg\n",
              worst_magnitude, worst_phase_deg);
  // Further from the load, less motion (at the lowest frequency, where the waves are longest).
  for (size_t k = 1; k < c.distanceCount(); ++k)
    EXPECT_LT(std::abs(c.compliance(k, 4.0)), std::abs(c.compliance(k - 1, 4.0)));
  EXPECT_THROW(c.compliance(c.distanceCount(), 10.0), std::out_of_range);
}

// The same run, short (the sanitizer build's stand-in for the test above, test/sanitizer/regular_only.txt):
// the response is linear in the force (the compliance does not change with it) and the two sides of the
// loaded footprint agree on this symmetric grid.
TEST(FootprintCompliance, ShortRunIsLinearAndSymmetric) {
  const SoilParams p = paramsOf(homogeneousScenario(4.2));
  FootprintComplianceSpec spec;
  spec.duration_s = 0.06;
  const FootprintCompliance a(p, spec);
  spec.force_n *= 3.0;
  const FootprintCompliance b(p, spec);
  ASSERT_EQ(a.distanceCount(), 3u);
  EXPECT_LT(static_cast<double>(a.summary()["side_difference"]), 1e-4);
  for (size_t k = 0; k < a.distanceCount(); ++k) {
    for (double f : {10.0, 20.0}) {
      EXPECT_NEAR(std::abs(b.compliance(k, f) / a.compliance(k, f) - 1.0), 0.0, 1e-5) << k << ", " << f << " Hz";
    }
  }
  EXPECT_GT(std::abs(a.compliance(0, 10.0)), std::abs(a.compliance(2, 10.0)));
}

// The footprint's consistent loads sum to the force and its mean of a uniform field is that field.
TEST(FootprintCompliance, FootprintWeightsAreAUnitLoad) {
  const StructuredMesh m =
      buildMesh({{1.0, kSoil}, {0.0, kSoil}}, MeshSpec{-3.0, 3.0, -2.0, 2.0, 3.0, 20.0, 8.0, 0.25, {}, 0.25});
  railvib::TrackLayout layout;
  layout.length_m = 2.6;
  layout.width_m = 0.25;
  for (double x : {0.0, 0.1, 0.37, -1.44}) {
    const ForceChannel ch = sleeperFootprint(m, x, layout);
    double sum = 0.0, first_moment = 0.0;
    for (size_t n = 0; n < ch.nodes.size(); ++n) {
      sum += ch.weights[n];
      first_moment += ch.weights[n] * m.x(ch.nodes[n] % (m.nx + 1));
    }
    EXPECT_NEAR(sum, 1.0, 1e-12) << "x = " << x;
    EXPECT_NEAR(first_moment, x, 1e-12) << "x = " << x;  // the load's resultant acts at the sleeper
    EXPECT_NEAR(footprintMean(ch, [](size_t, int) { return 2.5; }), 2.5, 1e-12);
  }
}

TEST(FootprintCompliance, BadSpecsAreRefused) {
  const SoilParams p = paramsOf(homogeneousScenario(6.0));
  auto refused = [&](FootprintComplianceSpec s) { EXPECT_THROW(FootprintCompliance(p, s), std::invalid_argument); };
  FootprintComplianceSpec s;
  s.force_n = 0.0;
  refused(s);
  s = {};
  s.pulse_s = std::nan("");
  refused(s);
  s = {};
  s.duration_s = 0.01;  // shorter than the pulse
  refused(s);
  s = {};
  s.pulse_s = 1e-6;  // below 4 steps
  refused(s);
  s = {};
  s.max_distance_m = -1.0;
  refused(s);
  // a box that holds one footprint on each side of the loaded one (+-2.6 m less the 2 m PML)
  EXPECT_THROW(FootprintCompliance(paramsOf(homogeneousScenario(3.0)), FootprintComplianceSpec{}),
               std::invalid_argument);
}

// A rail seat's share of the footprint: unit resultant at the seat (the first moments give its
// position), a linear pressure across the track; the two seats' weights add up to twice the
// footprint's.
TEST(FootprintCompliance, RailSeatWeightsPutTheLoadAtTheSeat) {
  const StructuredMesh m =
      buildMesh({{1.0, kSoil}, {0.0, kSoil}}, MeshSpec{-3.0, 3.0, -2.0, 2.0, 3.0, 20.0, 8.0, 0.25, {}, 0.25});
  railvib::TrackLayout layout;
  layout.length_m = 2.6;
  layout.width_m = 0.25;
  for (double x : {0.0, 0.37}) {
    for (double seat : {0.7175, -0.7175, 0.0, 1.3}) {
      const ForceChannel ch = railSeatFootprint(m, x, seat, layout);
      double sum = 0.0, mx = 0.0, my = 0.0;
      for (size_t n = 0; n < ch.nodes.size(); ++n) {
        const size_t i = ch.nodes[n] % (m.nx + 1), j = ch.nodes[n] / (m.nx + 1);
        sum += ch.weights[n];
        mx += ch.weights[n] * m.x(i);
        my += ch.weights[n] * m.y(j);
      }
      EXPECT_NEAR(sum, 1.0, 1e-12) << x << ", " << seat;
      EXPECT_NEAR(mx, x, 1e-12) << x << ", " << seat;
      EXPECT_NEAR(my, seat, 1e-12) << x << ", " << seat;
    }
    const ForceChannel whole = sleeperFootprint(m, x, layout);
    const ForceChannel left = railSeatFootprint(m, x, 0.7175, layout), right = railSeatFootprint(m, x, -0.7175, layout);
    ASSERT_EQ(left.nodes, whole.nodes);
    ASSERT_EQ(right.nodes, whole.nodes);
    for (size_t n = 0; n < whole.nodes.size(); ++n) {
      EXPECT_NEAR(left.weights[n] + right.weights[n], 2.0 * whole.weights[n], 1e-15);
    }
  }
}
