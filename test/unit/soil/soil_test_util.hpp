// Shared helpers of the soil unit tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/rigid_body.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil::testing {

/// The track's load stream rate in the small scenarios (track.output.load_sample_rate_hz).
inline constexpr double kLoadRateHz = 2000.0;
/// The Haren top layer's stiffness and density with nu = 0.25 (Vs 114 m/s, Vp 197 m/s), and concrete.
inline const Material kSoil{61.0e6, 1876.0, 0.25};
inline const Material kConcrete{20.0e9, 2400.0, 0.2};

/// The soil parameters of a scenario's YAML text.
inline SoilParams paramsOf(const std::string& yaml) {
  return loadSoilParams(railvib::Config::fromString(yaml, "test.yaml").root());
}

/// The scenario is refused with a ConfigError whose message holds `fragment`.
inline void expectConfigError(const std::string& yaml, const std::string& fragment) {
  try {
    paramsOf(yaml);
    ADD_FAILURE() << "no ConfigError for " << fragment;
  } catch (const railvib::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

/// A small self-contained scenario (homogeneous-ish 2-layer soil, short track);
/// `extra` is appended at the end of the YAML text (overrides by later keys are not
/// supported by YAML maps, so tests build variants with the arguments).
inline std::string smallScenario(const std::string& layer1 =
                                     "{thickness_m: 1.0, young_modulus_pa: 61.0e6, "
                                     "density_kg_m3: 1876.0, poisson_ratio: 0.13}",
                                 const std::string& mesh_extra = "",
                                 const std::string& sensors = "[{name: s2, x_m: 0.0, y_m: 2.0}]") {
  return "soil:\n"
         "  layers:\n"
         "    - " +
         layer1 +
         "\n"
         "  half_space: {young_modulus_pa: 465.0e6, density_kg_m3: 1992.0, poisson_ratio: 0.3}\n"
         "  rayleigh_beta_s: 4.0e-4\n"
         "  mesh: {f_max_hz: 20.0, elements_per_wavelength: 8.0, x_min_m: -4.0, x_max_m: 4.0, y_min_m: -4.0,"
         " y_max_m: 4.0, depth_m: 4.0" +
         mesh_extra +
         "}\n"
         "  boundary: {method: dashpots}\n"
         "  loads: {outside_mesh: drop, drop_min_receiver_distance_m: 0.0}\n"
         "  output: {receiver_rate_hz: 1000.0, snapshot_rate_hz: 100.0}\n"
         "track:\n"
         "  sleeper: {spacing_m: 0.72, length_m: 2.6, width_m: 0.25}\n"
         "  extent: {mode: fixed, x_min_m: -5.0, x_max_m: 5.0}\n"
         "  output: {load_sample_rate_hz: 2000.0}\n"
         "site:\n"
         "  rail_gauge_m: 1.435\n"
         "  ground_sensors: " +
         sensors +
         "\n"
         "simulation: {duration_s: 0.1}\n";
}

// Three-material layered soil (Haren layers 1-2 and a half-space), 0.25 m in plane, 20 element
// levels: nx x ny x 20 elements (48 x 40 x 20 = 38 400 in the thread and rank tests).
inline StructuredMesh layeredTestMesh(size_t nx, size_t ny) {
  const Material l1{61.0e6, 1876.0, 0.13}, l2{84.0e6, 1876.0, 0.13}, hs{465.0e6, 1992.0, 0.3};
  std::vector<double> z{0.0};
  std::vector<Material> mats;
  auto add = [&](int levels, double dz, const Material& m) {
    for (int k = 0; k < levels; ++k) {
      z.push_back(z.back() + dz);
      mats.push_back(m);
    }
  };
  add(6, 0.2, l1);
  add(8, 0.225, l2);
  add(6, 0.5, hs);
  return buildUniformMesh(nx, ny, 0.25, 0.25, z, mats, -6.0, -5.0);
}

inline double maxAbs(const std::vector<double>& a) {
  double m = 0.0;
  for (double x : a) m = std::max(m, std::abs(x));
  return m;
}

/// Largest |a_i - b_i|; infinite when the sizes differ (a run that lost or gained values never agrees).
inline double maxAbsDiff(const std::vector<double>& a, const std::vector<double>& b) {
  double d = a.size() == b.size() ? 0.0 : INFINITY;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// A two-storey superstructure on a rigid body (soil frame, reference on the ground): its mass above the
// reference point couples sway to rocking; two fixed-interface modes at 12 and 27 Hz.
inline ReducedStructure twoModeStructure(double damping_ratio) {
  ReducedStructure st;
  st.rigid_mass.diagonal() << 3000.0, 3000.0, 3000.0, 6000.0, 6000.0, 5000.0;
  st.rigid_mass(0, 4) = st.rigid_mass(4, 0) = -4000.0;
  st.rigid_mass(1, 3) = st.rigid_mass(3, 1) = 4000.0;
  st.participation.resize(2, 6);
  st.participation << 30.0, 0.0, 5.0, 0.0, 20.0, 0.0,  //
      0.0, 0.0, 40.0, 8.0, 0.0, 0.0;
  st.circular_frequency_rad_s.resize(2);
  st.circular_frequency_rad_s << 2.0 * M_PI * 12.0, 2.0 * M_PI * 27.0;
  st.damping_ratio = Eigen::VectorXd::Constant(2, damping_ratio);
  return st;
}

// The leapfrog's potential energy, 1/2 u_n K u_{n+1} of the soil plus 1/2 w^2 eta_n eta_{n+1} of the
// modes of rigid body 0 (`modal_circular_frequency_rad_s`: its structure's): call after every step.
class LeapfrogPotential {
 public:
  LeapfrogPotential(const Solver& s, const Eigen::VectorXd& modal_circular_frequency_rad_s)
      : w2_(modal_circular_frequency_rad_s.cwiseAbs2()), eta_prev_(Eigen::VectorXd::Zero(w2_.size())) {
    remember(s);
  }
  double afterStep(const Solver& s) {
    s.internalForce(f_);  // -K u_{n+1}
    double e = 0.0;
    for (size_t q = 0; q < f_.size(); ++q) e -= 0.5 * u_prev_[q] * f_[q];
    const RigidBodyState& b = s.rigidBody(0);
    for (long i = 0; i < w2_.size(); ++i) e += 0.5 * w2_[i] * eta_prev_[i] * b.modal_displacement[i];
    remember(s);
    eta_prev_ = b.modal_displacement;
    return e;
  }

 private:
  void remember(const Solver& s) {
    const size_t n = s.mesh().nodeCount();
    u_prev_.resize(3 * n);
    for (size_t nd = 0; nd < n; ++nd)
      for (int c = 0; c < 3; ++c) u_prev_[3 * nd + c] = s.displacement(nd, c);
  }
  Eigen::VectorXd w2_, eta_prev_;
  std::vector<double> u_prev_, f_;
};

}  // namespace railvib::soil::testing
