#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "railvib/soil/lamb.hpp"

using namespace railvib::soil;

// Analytic half-space solution: arrival times, static (Boussinesq) limit.
TEST(SoilLamb, PekerisArrivalsAndStaticLimit) {
  for (double nu : {0.13, 0.25, 0.33, 0.4}) {
    const Material m{1.0e8, 2000.0, nu};
    const PekerisSolution p(m);
    EXPECT_NEAR(p.tauP(), m.vs() / m.vp(), 1e-12);
    EXPECT_NEAR(p.tauR(), m.vs() / m.vr(), 1e-12);
    // Nothing before the P wave, motion right after it.
    EXPECT_EQ(p.stepNormalised(0.999 * p.tauP()), 0.0);
    EXPECT_GT(std::abs(p.stepNormalised(p.tauP() + 0.05)), 1e-4);
    // The largest motion is at the Rayleigh arrival (singular there).
    EXPECT_GT(std::abs(p.stepNormalised(p.tauR() - 1e-6)), 10.0 * p.staticValue());
    // Static limit P (1 - nu) / (2 pi G r), reached after the Rayleigh wave.
    const double r = 5.0, P = 1.0e4;
    const double w_static = P * (1.0 - nu) / (2.0 * M_PI * m.shearModulus() * r);
    EXPECT_NEAR(p.stepDisplacement(P, r, 50.0 * r / m.vs()), w_static, 1e-4 * w_static);
    EXPECT_NEAR(p.stepDisplacement(P, r, 1.5 * p.tauR() * r / m.vs()), w_static, 1e-3 * w_static);
  }
  // Pekeris (nu = 1/4): Rayleigh arrival at tau_R = 1 / 0.9194 = 1.0877 (classical value).
  EXPECT_NEAR(PekerisSolution(Material{1e8, 2000, 0.25}).tauR(), 1.08766, 2e-5);
}

TEST(SoilLamb, SmoothStepResponseTendsToStatic) {
  const Material m{2.5e7, 2000.0, 0.25};
  const PekerisSolution p(m);
  const double r = 4.0, P = 1e4;
  const auto w = p.smoothStepResponse(P, r, 0.05, {0.01, 0.3, 1.0});
  EXPECT_NEAR(w[0], 0.0, 1e-15);  // before the P arrival r / Vp = 0.033 s
  const double w_static = P * 0.75 / (2.0 * M_PI * m.shearModulus() * r);
  EXPECT_NEAR(w[2], w_static, 2e-3 * w_static);
}

// FE vs analytic: Hann pulse on a quarter half-space, 13 elements per Rayleigh wavelength
// at the pulse's dominant frequency: P and Rayleigh arrivals within 2 %, peak within 10 %.
// Both kernels; the stencil's surface traces equal the element kernel's to float round-off
// (a step's round-off u = 2^-24 of the peak per step at most, as in SoilThreads).
TEST(SoilLamb, FiniteElementsMatchPekeris) {
  LambSpec spec;
  const LambResult element = runLamb(spec);
  spec.kernel = KernelKind::Stencil;
  const LambResult stencil = runLamb(spec);
  for (const LambResult* r : {&element, &stencil}) {
    ASSERT_EQ(r->stations.size(), 3u);
    for (const auto& s : r->stations) {
      EXPECT_GE(s.elements_per_rayleigh_wavelength, 10.0);
      EXPECT_NEAR(s.t_p_fe_s / s.t_p_an_s, 1.0, 0.02) << "r = " << s.r_m;
      EXPECT_NEAR(s.t_r_fe_s / s.t_r_an_s, 1.0, 0.02) << "r = " << s.r_m;
      EXPECT_NEAR(s.peak_fe_m / s.peak_an_m, 1.0, 0.10) << "r = " << s.r_m;
      std::printf("%s: r = %.1f m: P arrival %+.2f %%, Rayleigh %+.2f %%, peak %+.2f %%\n",
                  r == &element ? "element" : "stencil", s.r_m, 100 * (s.t_p_fe_s / s.t_p_an_s - 1),
                  100 * (s.t_r_fe_s / s.t_r_an_s - 1), 100 * (s.peak_fe_m / s.peak_an_m - 1));
    }
  }
  ASSERT_EQ(element.t_s.size(), stencil.t_s.size());
  for (size_t k = 0; k < element.stations.size(); ++k) {
    double diff = 0.0;
    for (size_t i = 0; i < element.t_s.size(); ++i) {
      diff = std::max(diff, std::abs(element.w_fe[k][i] - stencil.w_fe[k][i]));
    }
    const double peak = element.stations[k].peak_fe_m;
    std::printf("r = %.1f m: max |stencil - element| / peak %.2e\n", element.stations[k].r_m, diff / peak);
    EXPECT_LE(diff, static_cast<double>(element.t_s.size()) * std::ldexp(1.0, -24) * peak);
  }
}
