// Passive isolation by an open and a soft-filled trench on a homogeneous half-space (soil/screening.hpp),
// against the published criteria: Woods (1968, field tests): an open trench brings the amplitude
// reduction ratio A_r to 0.25 or less once its depth reaches 0.6 Rayleigh wavelengths (active) to 1.33
// (passive); Segol, Lee & Abel (J. Eng. Mech. Div. ASCE 104, 1978): depth / wavelength is the governing
// parameter, and above 0.6 the disturbance is significantly reduced; backfilled trenches screen less than
// open ones (also Ahmad & Al-Hussaini, J. Geotech. Eng. 117(1), 1991). A coarse mesh (0.25 m, 25-45 Hz,
// 8 elements per shear wavelength at 50 Hz): the 0.125 m mesh of `railvib_tool soil-bench trench` gives
// the same ratios within 0.02. One thread: the EPS fill's stable step makes it the longest run (~5 s).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "railvib/soil/screening.hpp"

using namespace railvib::soil;

TEST(SoilScreening, OpenTrenchScreensAsTheFieldTestsShowAndASoftFillLess) {
  ScreeningSpec spec = defaultScreeningSpec();
  spec.element_m = 0.25;
  spec.threads = 1;  // one thread: not slowed by whatever else runs beside the suite
  spec.frequencies_hz = {25.0, 30.0, 35.0, 40.0, 45.0};
  spec.barriers.push_back({"soft fill 1.5 m", false, {8.0e6, 20.0, 0.1}, 1.5});
  const ScreeningResult r = runScreening(spec);
  ASSERT_EQ(r.curves.size(), 3u);
  for (const ScreeningCurve& c : r.curves) {
    std::printf("%s:", c.name.c_str());
    for (size_t q = 0; q < c.amplitude_ratio.size(); ++q) {
      std::printf(" D/lambda %.2f A_r %.2f;", c.normalised_depth[q], c.amplitude_ratio[q]);
    }
    std::printf("\n");
  }
  const ScreeningCurve &shallow = r.curves[0], &deep = r.curves[1], &soft = r.curves[2];
  // A trench 0.2 wavelengths deep screens little, and more as its depth grows relative to the wavelength.
  EXPECT_GT(shallow.amplitude_ratio[0], 0.5);
  for (size_t q = 1; q < 4; ++q) EXPECT_LT(shallow.amplitude_ratio[q], shallow.amplitude_ratio[q - 1]) << q;
  for (size_t q = 0; q < 3; ++q) EXPECT_LT(deep.amplitude_ratio[q + 1], deep.amplitude_ratio[q] + 0.02) << q;
  // At 0.6 wavelengths and deeper, A_r <= 0.25 (Woods' criterion).
  for (size_t q = 0; q < deep.amplitude_ratio.size(); ++q) {
    if (deep.normalised_depth[q] >= 0.6) {
      EXPECT_LE(deep.amplitude_ratio[q], 0.25) << deep.normalised_depth[q];
    }
  }
  // The soft fill (EPS geofoam, impedance 0.047 x the soil's but 0.25 m thin: a spring between the trench's
  // faces, stiffness E_oed / W, that passes the low frequencies) screens less than the open trench of the
  // same depth at every frequency, and more as the frequency rises (its transmission ~ 1 / sqrt(1 + (omega
  // rho c W / 2 E_oed)^2) for a plane wave).
  for (size_t q = 0; q < soft.amplitude_ratio.size(); ++q) {
    EXPECT_GT(soft.amplitude_ratio[q], deep.amplitude_ratio[q] + 0.1) << q;
    EXPECT_LT(soft.amplitude_ratio[q], 0.9) << q;
    if (q > 0) {
      EXPECT_LT(soft.amplitude_ratio[q], soft.amplitude_ratio[q - 1]) << q;
    }
  }
}

// The same computation on a box too small to screen anything physical (0.5 m elements, 25-35 Hz, 60 ms),
// for the sanitizer build (test/sanitizer/regular_only.txt): a ratio per frequency and barrier, finite and
// positive, the depths normalised by the Rayleigh wavelength.
TEST(SoilScreening, ShortRunGivesARatioPerFrequencyAndBarrier) {
  ScreeningSpec spec = defaultScreeningSpec();
  spec.element_m = 0.5;
  spec.threads = 1;
  spec.frequencies_hz = {25.0, 30.0, 35.0};
  spec.duration_s = 0.06;
  spec.pml_m = 1.0;
  spec.barrier_width_m = 0.5;
  spec.barriers = {{"open", true, {}, 1.5}, {"soft", false, {8.0e6, 20.0, 0.1}, 1.5}};
  const ScreeningResult r = runScreening(spec);
  ASSERT_EQ(r.curves.size(), 2u);
  for (const ScreeningCurve& c : r.curves) {
    ASSERT_EQ(c.amplitude_ratio.size(), 3u);
    for (size_t q = 0; q < 3; ++q) {
      EXPECT_TRUE(std::isfinite(c.amplitude_ratio[q]) && c.amplitude_ratio[q] > 0.0) << c.name << " " << q;
      EXPECT_NEAR(c.normalised_depth[q], 1.5 * spec.frequencies_hz[q] / r.rayleigh_speed_m_s, 1e-12);
    }
  }
  EXPECT_GT(r.curves[1].dt_s, 0.0);
  EXPECT_LT(r.curves[1].dt_s, r.curves[0].dt_s);  // the EPS fill's P-wave speed lowers the stable step
}
