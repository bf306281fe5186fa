#include "railvib/soil/screening.hpp"

#include <chrono>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace railvib::soil {

ScreeningSpec defaultScreeningSpec() {
  ScreeningSpec s;
  s.barriers = {{"open trench 0.75 m", true, {}, 0.75}, {"open trench 1.5 m", true, {}, 1.5}};
  for (double f = 25.0; f <= 90.0 + 1e-9; f += 5.0) s.frequencies_hz.push_back(f);
  return s;
}

namespace {

size_t cells(double length_m, double h_m) { return static_cast<size_t>(std::llround(length_m / h_m)); }

// The surface nodes behind the barrier out to the largest zone (the lowest frequency's); per frequency the
// positions in `nodes` of its own zone.
struct Zone {
  std::vector<size_t> nodes;
  std::vector<std::vector<size_t>> of_frequency;
};

// One run: the surface z-displacement spectrum at the zone's nodes, |U(f)| per node and frequency.
std::vector<double> zoneSpectra(const ScreeningSpec& s, const StructuredMesh& mesh, const Zone& zone, double& dt_s,
                                double& seconds) {
  SolverOptions o;
  o.absorbing.y_min = false;
  o.symmetry_y_min = true;
  o.boundary.method = BoundaryMethod::Pml;
  o.boundary.pml.thickness_m = s.pml_m;
  o.boundary.pml.alpha_1_s = 30.0;
  o.kernel = KernelKind::Stencil;
  o.precision = s.precision;
  o.threads = s.threads;
  const auto t0 = std::chrono::steady_clock::now();
  Solver solver(mesh, o);
  dt_s = solver.dt();
  // The source at x = 0 on the symmetry plane: half of the point load.
  const size_t i0 = cells(-s.x_min_m, s.element_m);
  solver.addForceChannel({{mesh.node(i0, 0, 0)}, {2}, {0.5}});
  const size_t steps = static_cast<size_t>(std::ceil(s.duration_s / dt_s));
  const size_t nf = s.frequencies_hz.size(), nn = zone.nodes.size();
  std::vector<std::complex<double>> acc(nf * nn, 0.0);
  std::vector<std::complex<double>> rot(nf), phase(nf, 1.0);
  for (size_t q = 0; q < nf; ++q) rot[q] = std::polar(1.0, -2.0 * M_PI * s.frequencies_hz[q] * dt_s);
  for (size_t n = 0; n < steps; ++n) {
    const double t = solver.time();
    solver.setChannelValues({t < s.pulse_s ? 1.0e3 * (0.5 - 0.5 * std::cos(2.0 * M_PI * t / s.pulse_s)) : 0.0});
    solver.step();
    // u at t_{n+1}: Fourier sum with the phase of t_{n+1}.
    for (size_t q = 0; q < nf; ++q) phase[q] *= rot[q];
    for (size_t a = 0; a < nn; ++a) {
      const double u = solver.displacement(zone.nodes[a], 2);
      for (size_t q = 0; q < nf; ++q) acc[q * nn + a] += u * phase[q];
    }
  }
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<double> out(nf * nn);
  for (size_t q = 0; q < out.size(); ++q) out[q] = std::abs(acc[q]) * dt_s;
  return out;
}

}  // namespace

ScreeningResult runScreening(const ScreeningSpec& s) {
  if (!(s.element_m > 0.0) || s.frequencies_hz.empty() || !(s.duration_s > s.pulse_s) || !(s.pulse_s > 0.0)) {
    throw std::invalid_argument("screening: element size, frequencies, pulse and duration must be positive");
  }
  const double h = s.element_m;
  const size_t nx = cells(s.x_max_m - s.x_min_m, h), ny = cells(s.y_max_m, h), nz = cells(s.depth_m, h);
  if (nx < 8 || ny < 8 || nz < 8 || static_cast<double>(nx) * ny * nz > 5.0e6) {
    throw std::invalid_argument("screening: the box has too few or too many elements for this element size");
  }
  std::vector<double> z;
  for (size_t k = 0; k <= nz; ++k) z.push_back(h * static_cast<double>(k));
  const StructuredMesh base = buildUniformMesh(nx, ny, h, h, z, std::vector<Material>(nz, s.soil), s.x_min_m, 0.0);
  // The zones behind the barrier, one per frequency, in its Rayleigh wavelengths.
  const double c_r = s.soil.vr(), x_far = s.barrier_x_m + s.barrier_width_m;
  Zone zone;
  for (size_t j = 0; j <= ny; ++j) {
    for (size_t i = 0; i <= nx; ++i) {
      const double x = base.x(i), y = base.y(j);
      bool any = false;
      for (double f : s.frequencies_hz) {
        const double lambda = c_r / f;
        any = any || (x >= x_far + s.zone_start_wavelengths * lambda - 1e-9 &&
                      x <= x_far + (s.zone_start_wavelengths + s.zone_length_wavelengths) * lambda + 1e-9 &&
                      y <= s.zone_half_width_wavelengths * lambda + 1e-9);
      }
      if (any) zone.nodes.push_back(base.node(i, j, 0));
    }
  }
  const double room_x = s.x_max_m - s.pml_m, room_y = s.y_max_m - s.pml_m;
  for (double f : s.frequencies_hz) {
    const double lambda = c_r / f;
    if (x_far + (s.zone_start_wavelengths + s.zone_length_wavelengths) * lambda > room_x ||
        s.zone_half_width_wavelengths * lambda > room_y) {
      throw std::invalid_argument("screening: the zone of " + std::to_string(f) + " Hz reaches the PML");
    }
    std::vector<size_t> mine;
    for (size_t a = 0; a < zone.nodes.size(); ++a) {
      const size_t nd = zone.nodes[a], i = nd % (nx + 1), j = (nd / (nx + 1)) % (ny + 1);
      if (base.x(i) >= x_far + s.zone_start_wavelengths * lambda - 1e-9 &&
          base.x(i) <= x_far + (s.zone_start_wavelengths + s.zone_length_wavelengths) * lambda + 1e-9 &&
          base.y(j) <= s.zone_half_width_wavelengths * lambda + 1e-9) {
        mine.push_back(a);
      }
    }
    if (mine.empty())
      throw std::invalid_argument("screening: no surface node in the zone of " + std::to_string(f) + " Hz");
    zone.of_frequency.push_back(mine);
  }
  ScreeningResult r;
  r.rayleigh_speed_m_s = c_r;
  r.elements = base.elementCount();
  for (const auto& z : zone.of_frequency) r.zone_nodes.push_back(z.size());
  r.frequencies_hz = s.frequencies_hz;
  double dt = 0.0;
  const std::vector<double> without = zoneSpectra(s, base, zone, dt, r.reference_seconds);
  const size_t nf = s.frequencies_hz.size(), nn = zone.nodes.size();
  for (const BarrierCase& b : s.barriers) {
    StructuredMesh mesh = base;
    InclusionSpec inc;
    inc.name = b.name;
    inc.is_void = b.is_void;
    inc.material = b.fill;
    inc.x_min_m = s.barrier_x_m, inc.x_max_m = s.barrier_x_m + s.barrier_width_m;
    inc.y_min_m = 0.0, inc.y_max_m = s.barrier_half_length_m;
    inc.top_m = 0.0, inc.bottom_m = b.depth_m;
    addInclusions(mesh, {inc}, 0.51 * h);  // nearest faces: at most half an element away
    ScreeningCurve c;
    c.name = b.name;
    c.depth_m = b.depth_m;
    const std::vector<double> with = zoneSpectra(s, mesh, zone, c.dt_s, c.seconds);
    for (size_t q = 0; q < nf; ++q) {
      double sum = 0.0;
      for (size_t a : zone.of_frequency[q]) sum += with[q * nn + a] / without[q * nn + a];
      c.amplitude_ratio.push_back(sum / static_cast<double>(zone.of_frequency[q].size()));
      c.normalised_depth.push_back(b.depth_m * s.frequencies_hz[q] / r.rayleigh_speed_m_s);
    }
    r.curves.push_back(c);
  }
  return r;
}

}  // namespace railvib::soil
