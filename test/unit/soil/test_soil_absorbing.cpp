// Absorbing layer (docs/soil.md, "Boundary reflections"): the Lamb Hann pulse on a
// quarter half-space, surface displacement at r = 6 m, in an 8 m box with Lysmer
// dashpots, in the same box plus a 4 m linear mass-proportional layer along the
// sides, and in a 15 m reference box whose own reflections come back after the
// window (0.37 s). The reflected / direct rms ratio over 10-50 Hz must fall from
// ~24 % (dashpots only) to below 6 % with the layer (measured 3.4 % in this window,
// 4.1 % in the 0.52 s window of `soil-bench reflection`), and to below half of what
// the same 12 m box gives without the layer (9.6 %): the bound fails for a layer
// that does nothing.
#include <gtest/gtest.h>

#include <cstdio>

#include "railvib/soil/lamb.hpp"

using namespace railvib::soil;

TEST(SoilAbsorbing, LayerCutsSurfaceWaveReflection) {
  LambSpec ref;
  ref.distances_m = {6.0};
  ref.half_width_m = ref.depth_m = 15.0;
  // The reference's own side reflection (Rayleigh) reaches r after (2 W - r) / c_R = 0.37 s.
  const double window = (2.0 * ref.half_width_m - 6.0) / ref.material.vr();
  ref.duration_s = window;
  const LambResult a = runLamb(ref);

  LambSpec small = ref;
  small.half_width_m = small.depth_m = 8.0;
  const LambResult lysmer = runLamb(small);

  small.half_width_m = 12.0;  // the layer lies outside the 8 m box of interest
  small.boundary = ReflectionCase::gradedLayer(4.0, 60.0, 1.0, false).boundary;
  const LambResult layer = runLamb(small);

  small.boundary = BoundarySpec{};  // same 12 m box, dashpots only
  const LambResult bigger = runLamb(small);

  const ReflectionRow r_lysmer = reflectionFigures(lysmer.w_fe[0], a.w_fe[0], a.dt_s);
  const ReflectionRow r_layer = reflectionFigures(layer.w_fe[0], a.w_fe[0], a.dt_s);
  const ReflectionRow r_bigger = reflectionFigures(bigger.w_fe[0], a.w_fe[0], a.dt_s);
  std::printf("10-50 Hz reflected/direct: Lysmer 8 m box %.3f, 12 m box %.3f, 8 m box + 4 m layer %.3f\n",
              r_lysmer.band_10_50, r_bigger.band_10_50, r_layer.band_10_50);
  EXPECT_GT(r_lysmer.band_10_50, 0.15);  // the problem is there
  EXPECT_LT(r_layer.band_10_50, 0.06);
  EXPECT_LT(r_layer.band_10_50, 0.5 * r_bigger.band_10_50);  // the damping, not just the larger box
  for (double b : {r_layer.band_10_20, r_layer.band_20_35, r_layer.band_35_50}) EXPECT_LT(b, 0.08);
  // The mass-proportional layer changes neither the step nor the direct wave before it can reflect.
  EXPECT_EQ(layer.dt_s, a.dt_s);
}
