// railvib/soil: screening of surface waves by a trench or a wall (passive isolation), the case of the
// published field tests and design charts: Woods, J. Soil Mech. Found. Div. ASCE 94(4), 1968 (field
// tests); Beskos, Dasgupta & Vardoulakis, Comput. Geotech. 1, 1986 (boundary elements); Ahmad &
// Al-Hussaini, J. Geotech. Eng. 117(1), 1991 (design charts). A vertical point load with a broadband
// pulse on a homogeneous half-space; a barrier (an open trench, a soft or a stiff in-fill, through
// soil.inclusions' seam: MeshSpec::inclusions) at a distance, parallel to the wave fronts' mean; the
// amplitude reduction ratio A_r(f) = mean over a zone behind the barrier of |U_z,with(f)| / |U_z,without(f)|
// (Woods' definition), read per frequency, i.e. per normalised depth D / lambda_R = D f / c_R.
#pragma once

#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

struct BarrierCase {
  std::string name;
  bool is_void = true;
  Material fill;  // unless a void
  double depth_m = 1.5;
};

struct ScreeningSpec {
  /// Homogeneous half-space (nu = 0.25 as in Woods' site and most charts).
  Material soil{45.0e6, 1800.0, 0.25};
  double element_m = 0.125;
  /// Half model: the symmetry plane y = 0 holds the source; x along the wave path.
  double x_min_m = -2.5, x_max_m = 13.0, y_max_m = 6.0, depth_m = 7.0;
  double pml_m = 1.5;
  /// The barrier: x [x, x + width], y [0, half_length], depth [0, depth].
  double barrier_x_m = 3.0, barrier_width_m = 0.25, barrier_half_length_m = 4.5;
  std::vector<BarrierCase> barriers;
  /// The zone behind the barrier where A_r is averaged, in Rayleigh wavelengths of each frequency (the
  /// normalised geometry of the charts): the surface nodes from the barrier's far face over
  /// zone_length_wavelengths, |y| <= zone_half_width_wavelengths, starting zone_start_wavelengths behind it.
  double zone_start_wavelengths = 0.0, zone_length_wavelengths = 2.0, zone_half_width_wavelengths = 1.0;
  /// Hann pulse (broadband to ~2 / pulse_s) and the recorded time.
  double pulse_s = 0.008, duration_s = 0.35;
  std::vector<double> frequencies_hz;
  Precision precision = Precision::Float;
  int threads = 0;
};

/// The default: the open trench 0.75 m and 1.5 m deep, 25-90 Hz (D / lambda_R 0.2 to 1.5).
ScreeningSpec defaultScreeningSpec();

struct ScreeningCurve {
  std::string name;
  double depth_m = 0.0;
  double dt_s = 0.0;
  double seconds = 0.0;
  std::vector<double> normalised_depth;  // D / lambda_R per frequency
  std::vector<double> amplitude_ratio;   // A_r per frequency
};

struct ScreeningResult {
  double rayleigh_speed_m_s = 0.0;
  size_t elements = 0;
  std::vector<size_t> zone_nodes;  // per frequency
  double reference_seconds = 0.0;
  std::vector<double> frequencies_hz;
  std::vector<ScreeningCurve> curves;
};

/// The run without a barrier, then one per barrier. Throws std::invalid_argument on an impossible spec.
ScreeningResult runScreening(const ScreeningSpec& spec);

}  // namespace railvib::soil
