// railvib/soil: verification of the soil-structure interaction model against published solutions
// (ssi_verification.hpp).
#include "railvib/soil/ssi_verification.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "railvib/signal/decimator.hpp"
#include "railvib/signal/third_octave.hpp"

namespace railvib::soil {

double hannPulse(double t_s, double duration_s) {
  return t_s < 0.0 || t_s >= duration_s ? 0.0 : 0.5 * (1.0 - std::cos(2.0 * M_PI * t_s / duration_s));
}

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Linear interpolation in a table (x increasing), clamped at the ends.
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double v) {
  if (v <= x.front()) return y.front();
  if (v >= x.back()) return y.back();
  const size_t k = static_cast<size_t>(std::upper_bound(x.begin(), x.end(), v) - x.begin());
  const double f = (v - x[k - 1]) / (x[k] - x[k - 1]);
  return y[k - 1] + f * (y[k] - y[k - 1]);
}

// One sine cycle under a Hann window: no net impulse, so the floating box of a model with dashpots on every
// far face drifts back to rest instead of keeping an offset (J / c_dashpots) in the footing's displacement.
double zeroImpulseWavelet(double t, double duration) {
  return hannPulse(t, duration) * std::sin(2.0 * M_PI * t / duration);
}

// Fourier transform sum x_n exp(-i w t_n) dt of a sampled record.
std::complex<double> fourier(const std::vector<double>& t, const std::vector<double>& x, double omega, double dt) {
  std::complex<double> sum = 0.0;
  for (size_t n = 0; n < x.size(); ++n) sum += x[n] * std::polar(1.0, -omega * t[n]);
  return sum * dt;
}

// Cubes of side h over [0, box]^3, one material.
StructuredMesh quarterBox(const FootingModelSpec& spec, double box_m) {
  const size_t n = static_cast<size_t>(std::llround(box_m / spec.h_m));
  const size_t nb = static_cast<size_t>(std::llround(spec.half_width_m / spec.h_m));
  if (n < nb + 2 || std::abs(static_cast<double>(nb) * spec.h_m - spec.half_width_m) > 1e-9 * spec.half_width_m) {
    throw std::invalid_argument("ssi verification: the footing half width must be a multiple of h inside the box");
  }
  std::vector<double> z(n + 1);
  for (size_t k = 0; k <= n; ++k) z[k] = spec.h_m * static_cast<double>(k);
  StructuredMesh mesh = buildUniformMesh(n, n, spec.h_m, spec.h_m, z, std::vector<Material>(n, spec.material));
  auto onPlanes = [&](double v) { return std::abs(v / spec.h_m - std::round(v / spec.h_m)) < 1e-9; };
  if (!onPlanes(spec.embedment_m) || spec.embedment_m < 0.0 || spec.embedment_m > box_m - 2.0 * spec.h_m) {
    throw std::invalid_argument("ssi verification: the embedment must be a multiple of h inside the box");
  }
  if (!spec.meshed) return mesh;
  const double b = spec.half_width_m, d = spec.embedment_m, t = spec.wall_m > 0.0 ? spec.wall_m : spec.h_m;
  if (!onPlanes(t) || d < 2.0 * t + spec.h_m || b < t + spec.h_m) {
    throw std::invalid_argument(
        "ssi verification: a meshed foundation needs walls a multiple of h and a cavity of one element at least");
  }
  // The quarter of the box (symmetry planes x = 0 and y = 0): top and base slabs, the two outer walls.
  auto box = [&](const char* name, double x0, double x1, double y0, double y1, double z0, double z1) {
    InclusionSpec s;
    s.name = name;
    s.material = spec.concrete;
    s.implicit = true;
    s.rayleigh_beta_s = spec.concrete_beta_s;
    s.x_min_m = x0, s.x_max_m = x1, s.y_min_m = y0, s.y_max_m = y1, s.top_m = z0, s.bottom_m = z1;
    return s;
  };
  addInclusions(mesh,
                {box("top_slab", 0.0, b, 0.0, b, 0.0, t), box("base_slab", 0.0, b, 0.0, b, d - t, d),
                 box("wall_x", b - t, b, 0.0, b, t, d - t), box("wall_y", 0.0, b - t, b - t, b, t, d - t)},
                1e-6 * spec.h_m);
  return mesh;
}

// The footing [0, B]^2 at the surface, reference point at the centre of the full footing; only the DOF of
// the mode is free (the quarter model's planes hold the others, and pure rocking holds the sway).
RigidBodySpec footingBody(const FootingModelSpec& spec, FootingMode mode) {
  RigidBodySpec body;
  body.name = "footing";
  body.x_min_m = body.y_min_m = 0.0;
  body.x_max_m = body.y_max_m = spec.half_width_m;
  // Rigid: the soil nodes down to the embedment; meshed: the concrete's top face.
  body.depth_m = spec.meshed ? 0.0 : spec.embedment_m;
  body.snap_tolerance_m = 1e-6 * spec.h_m;
  body.held.fill(true);
  body.held[mode == FootingMode::Vertical ? 2 : 3] = false;
  return body;
}

// The load of the quarter model: a vertical force on one carried node. For rocking it sits at y = B on
// x = 0 and gives the moment B P about the x axis (its vertical part acts on a held DOF).
size_t addFootingLoad(Solver& s, const FootingModelSpec& spec, FootingMode mode) {
  const size_t nb = static_cast<size_t>(std::llround(spec.half_width_m / spec.h_m));
  ForceChannel ch;
  ch.nodes = {s.mesh().node(0, mode == FootingMode::Vertical ? 0 : nb, 0)};
  ch.components = {2};
  ch.weights = {1.0};
  return s.addForceChannel(ch);
}

SolverOptions footingOptions(const FootingModelSpec& spec, FootingMode mode, bool absorbing) {
  SolverOptions o;
  o.absorbing = {false, absorbing, false, absorbing, absorbing};
  o.symmetry_x_min = true;
  if (mode == FootingMode::Vertical) {
    o.symmetry_y_min = true;
  } else {
    o.antisymmetry_y_min = true;
  }
  o.precision = spec.precision;
  o.threads = spec.threads;
  return o;
}

}  // namespace

double extrapolatePower(double x1, double v1, double x2, double v2, double q) {
  const double s1 = std::pow(x1, q), s2 = std::pow(x2, q);
  return (s1 * v2 - s2 * v1) / (s1 - s2);
}

double convergenceOrder(double x1, double v1, double x2, double v2, double x3, double v3) {
  // (v1 - v2) / (v2 - v3) = (x1^q - x2^q) / (x2^q - x3^q), which grows with q.
  const double ratio = (v1 - v2) / (v2 - v3);
  auto g = [&](double q) { return (std::pow(x1, q) - std::pow(x2, q)) / (std::pow(x2, q) - std::pow(x3, q)) - ratio; };
  double lo = 0.05, hi = 8.0;
  if (!(g(lo) < 0.0 && g(hi) > 0.0)) throw std::runtime_error("ssi verification: values not in a power-law regime");
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// ---- Published closed forms ----

double gazetasVerticalStiffness(const Material& m, double l_m, double b_m) {
  const double chi = (4.0 * l_m * b_m) / (4.0 * l_m * l_m);
  return 2.0 * m.shearModulus() * l_m / (1.0 - m.poisson_ratio) * (0.73 + 1.54 * std::pow(chi, 0.75));
}

double gazetasEmbeddedVerticalStiffness(const Material& m, double l_m, double b_m, double d_m) {
  const double chi = (4.0 * l_m * b_m) / (4.0 * l_m * l_m);
  const double wall_area = 2.0 * (2.0 * l_m + 2.0 * b_m) * d_m, base_area = 4.0 * l_m * b_m;
  return gazetasVerticalStiffness(m, l_m, b_m) * (1.0 + d_m / (21.0 * b_m) * (1.0 + 1.3 * chi)) *
         (1.0 + 0.2 * std::pow(wall_area / base_area, 2.0 / 3.0));
}

double gazetasRockingStiffnessX(const Material& m, double l_m, double b_m) {
  const double i_bx = (2.0 * l_m) * std::pow(2.0 * b_m, 3) / 12.0;
  return m.shearModulus() / (1.0 - m.poisson_ratio) * std::pow(i_bx, 0.75) * std::pow(l_m / b_m, 0.25) *
         (2.4 + 0.5 * b_m / l_m);
}

double gazetasRockingStiffnessY(const Material& m, double l_m, double b_m) {
  const double i_by = (2.0 * b_m) * std::pow(2.0 * l_m, 3) / 12.0;
  return 3.0 * m.shearModulus() / (1.0 - m.poisson_ratio) * std::pow(i_by, 0.75) * std::pow(l_m / b_m, 0.15);
}

double paisKauselVerticalStiffness(const Material& m, double l_m, double b_m) {
  return m.shearModulus() * b_m / (1.0 - m.poisson_ratio) * (3.1 * std::pow(l_m / b_m, 0.75) + 1.6);
}

double paisKauselEmbeddedVerticalStiffness(const Material& m, double l_m, double b_m, double d_m) {
  return paisKauselVerticalStiffness(m, l_m, b_m) * (1.0 + (0.25 + 0.25 * b_m / l_m) * std::pow(d_m / b_m, 0.8));
}

double paisKauselRockingStiffnessX(const Material& m, double l_m, double b_m) {
  return m.shearModulus() * std::pow(b_m, 3) / (1.0 - m.poisson_ratio) * (3.2 * l_m / b_m + 0.8);
}

double paisKauselRockingStiffnessY(const Material& m, double l_m, double b_m) {
  return m.shearModulus() * std::pow(b_m, 3) / (1.0 - m.poisson_ratio) * (3.73 * std::pow(l_m / b_m, 2.4) + 0.27);
}

VerticalImpedance paisKauselVerticalImpedance(const Material& m, double l_m, double b_m, double a0) {
  const double r = l_m / b_m;
  const double alpha = 1.0 - (0.4 + 0.2 / r) * a0 * a0 / (10.0 / (1.0 + 3.0 * (r - 1.0)) + a0 * a0);
  const double nu = m.poisson_ratio;
  const double psi = std::min(std::sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)), 2.5);
  return {paisKauselVerticalStiffness(m, l_m, b_m) * alpha, psi * m.density_kg_m3 * m.vs() * 4.0 * l_m * b_m};
}

VerticalImpedance gazetasSquareVerticalImpedance(const Material& m, double b_m, double a0) {
  // Digitised chart values of Gazetas (1991), Table 1 graphs, surface footing, nu <= 0.4: k_z on the
  // L/B = 1-2 curve, c_z on the L/B = 1 curve.
  static const std::vector<double> a_k = {0.0, 0.32, 0.67, 1.08, 1.44, 1.74, 2.0};
  static const std::vector<double> k_z = {1.0, 1.0, 0.967, 0.881, 0.787, 0.693, 0.600};
  static const std::vector<double> a_c = {0.0, 0.85, 1.59, 2.0};
  static const std::vector<double> c_z = {0.918, 0.946, 0.972, 1.001};
  const double v_la = 3.4 * m.vs() / (M_PI * (1.0 - m.poisson_ratio));
  return {gazetasVerticalStiffness(m, b_m, b_m) * interpolate(a_k, k_z, a0),
          m.density_kg_m3 * v_la * 4.0 * b_m * b_m * interpolate(a_c, c_z, a0)};
}

LysmerAnalog lysmerAnalog(const Material& m, double radius_m, double mass_kg) {
  LysmerAnalog a;
  const double g = m.shearModulus(), nu = m.poisson_ratio, rho = m.density_kg_m3;
  a.stiffness_n_m = 4.0 * g * radius_m / (1.0 - nu);
  a.dashpot_n_s_m = 3.4 * radius_m * radius_m * std::sqrt(g * rho) / (1.0 - nu);
  a.mass_kg = mass_kg;
  a.mass_ratio = (1.0 - nu) * mass_kg / (4.0 * rho * std::pow(radius_m, 3));
  const double wn = std::sqrt(a.stiffness_n_m / mass_kg);
  a.natural_hz = wn / (2.0 * M_PI);
  a.damping_ratio = a.dashpot_n_s_m / (2.0 * std::sqrt(a.stiffness_n_m * mass_kg));
  a.damped_hz = a.natural_hz * std::sqrt(1.0 - a.damping_ratio * a.damping_ratio);
  a.resonance_hz = a.natural_hz * std::sqrt(std::max(0.0, 1.0 - 2.0 * a.damping_ratio * a.damping_ratio));
  return a;
}

// ---- Static stiffness ----

StaticStiffnessRun runFootingStaticBox(const FootingModelSpec& spec, FootingMode mode, double box_m, double tolerance) {
  const auto t0 = Clock::now();
  const Material& mat = spec.material;
  const int dof = mode == FootingMode::Vertical ? 2 : 3;
  const double load_n = 1.0e4;
  const double generalised_load = mode == FootingMode::Vertical ? load_n : load_n * spec.half_width_m;
  SolverOptions o = footingOptions(spec, mode, false);
  o.fixed_bottom = true;
  // Critical damping of the lowest (shear) mode of the box: the slowest part of the static response.
  const double omega1 = M_PI * mat.vs() / (2.0 * box_m);
  o.mass_damping_1_s = 2.0 * omega1;
  Solver s(quarterBox(spec, box_m), o);
  s.attachRigidBody(footingBody(spec, mode));
  addFootingLoad(s, spec, mode);
  s.setChannelValues({load_n});
  const uint64_t check = std::max<uint64_t>(1, static_cast<uint64_t>(0.25 / (omega1 * s.dt())));
  const uint64_t max_steps = static_cast<uint64_t>(80.0 / (omega1 * s.dt()));
  double q_last = 0.0;
  StaticStiffnessRun run;
  run.box_m = s.mesh().xMax();
  run.elements = s.mesh().elementCount();
  while (run.steps < max_steps) {
    s.run(check);
    run.steps += check;
    const RigidBodyState& st = s.rigidBody(0);
    const double q = st.displacement[dof];
    run.residual = std::abs(st.soil_force[dof]) / generalised_load;
    std::fprintf(stderr, "DR step %lu q %.6e residual %.3e\n", (unsigned long)run.steps, q, run.residual);
    if (std::abs(q - q_last) < tolerance * std::abs(q) && run.residual < 10.0 * tolerance) break;
    q_last = q;
  }
  if (run.steps >= max_steps) throw std::runtime_error("ssi verification: dynamic relaxation did not converge");
  // Full footing: four times the quarter's force (vertical) or moment (rocking) for the same motion.
  run.stiffness = 4.0 * generalised_load / s.rigidBody(0).displacement[dof];
  run.seconds = secondsSince(t0);
  return run;
}

StaticStiffnessResult runFootingStatic(const FootingModelSpec& spec, FootingMode mode,
                                       const std::vector<double>& boxes_m, double tolerance) {
  if (boxes_m.size() < 3) throw std::invalid_argument("ssi verification: the static extrapolation needs 3 boxes");
  StaticStiffnessResult out;
  out.mode = mode;
  out.h_m = spec.h_m;
  const double b = spec.half_width_m;
  out.unit = spec.material.shearModulus() * (mode == FootingMode::Vertical ? b : b * b * b) /
             (1.0 - spec.material.poisson_ratio);
  for (double box : boxes_m) out.runs.push_back(runFootingStaticBox(spec, mode, box, tolerance));
  // Flexibility f = f_inf + a R^-p in x = 1 / R.
  const size_t n = out.runs.size();
  const StaticStiffnessRun &r1 = out.runs[n - 3], &r2 = out.runs[n - 2], &r3 = out.runs[n - 1];
  out.exponent = convergenceOrder(1.0 / r1.box_m, 1.0 / r1.stiffness, 1.0 / r2.box_m, 1.0 / r2.stiffness,
                                  1.0 / r3.box_m, 1.0 / r3.stiffness);
  out.extrapolated =
      1.0 / extrapolatePower(1.0 / r2.box_m, 1.0 / r2.stiffness, 1.0 / r3.box_m, 1.0 / r3.stiffness, out.exponent);
  out.extrapolated_inverse_r =
      1.0 / extrapolatePower(1.0 / r2.box_m, 1.0 / r2.stiffness, 1.0 / r3.box_m, 1.0 / r3.stiffness, 1.0);
  return out;
}

// ---- Dynamic vertical impedance ----

ImpedanceResult runFootingImpedance(const ImpedanceSpec& spec) {
  const auto t0 = Clock::now();
  const FootingModelSpec& fs = spec.footing;
  const Material& mat = fs.material;
  const double b = fs.half_width_m, vs = mat.vs();
  ImpedanceResult out;
  const double a0_max = *std::max_element(spec.a0.begin(), spec.a0.end());
  // The wavelet's spectrum peaks near 1 / T: at the top of the a0 range, so that the pulse is short and the
  // footing (massless: no resonance) is back at rest before the first reflection, from the bottom, returns.
  out.pulse_s = spec.pulse_s > 0.0 ? spec.pulse_s : 2.0 * M_PI * b / (a0_max * vs);
  out.window_s = spec.window_s > 0.0 ? spec.window_s : 2.0 * spec.box_m / mat.vp();
  Solver s(quarterBox(fs, spec.box_m), footingOptions(fs, FootingMode::Vertical, true));
  s.attachRigidBody(footingBody(fs, FootingMode::Vertical));
  addFootingLoad(s, fs, FootingMode::Vertical);
  out.dt_s = s.dt();
  out.elements = s.mesh().elementCount();
  const double load_n = 1.0e4;
  double u_n = 0.0;  // q_n: the footing's displacement at t_n, before the step
  while (s.time() < out.window_s) {
    const double t = s.time();
    const double f = load_n * zeroImpulseWavelet(t, out.pulse_s);
    s.setChannelValues({f});
    s.step();
    const RigidBodyState& st = s.rigidBody(0);
    out.t_s.push_back(t);
    out.displacement_m.push_back(u_n);
    // The footing is massless: the load balances the soil's reaction, and the lumped mass of the soil nodes it
    // carries (the top half element under it) is soil inertia, part of the impedance (quarter x 4).
    out.load_n.push_back(4.0 * f);
    out.soil_force_n.push_back(4.0 * (st.soil_force[2] - f));
    u_n = st.displacement[2];
  }
  out.steps = s.stepCount();
  double peak = 0.0;
  for (double u : out.displacement_m) peak = std::max(peak, std::abs(u));
  out.end_displacement = std::abs(out.displacement_m.back()) / peak;
  out.stiffness_unit = mat.shearModulus() * b / (1.0 - mat.poisson_ratio);
  out.dashpot_unit = mat.density_kg_m3 * vs * 4.0 * b * b;
  for (double a0 : spec.a0) {
    ImpedancePoint p;
    p.a0 = a0;
    const double omega = a0 * vs / b;
    p.frequency_hz = omega / (2.0 * M_PI);
    const std::complex<double> k =
        fourier(out.t_s, out.load_n, omega, out.dt_s) / fourier(out.t_s, out.displacement_m, omega, out.dt_s);
    p.fe = {k.real(), k.imag() / omega};
    p.gazetas = gazetasSquareVerticalImpedance(mat, b, a0);
    p.pais_kausel = paisKauselVerticalImpedance(mat, b, b, a0);
    out.points.push_back(p);
  }
  if (out.points.size() >= 2) {
    const double a1 = out.points[0].a0, a2 = out.points[1].a0;
    const double k1 = out.points[0].fe.stiffness_n_m, k2 = out.points[1].fe.stiffness_n_m;
    out.static_stiffness_n_m = (a2 * a2 * k1 - a1 * a1 * k2) / (a2 * a2 - a1 * a1);
  }
  out.seconds = secondsSince(t0);
  return out;
}

// ---- Massive block: Lysmer's analog ----

BlockResult runBlock(const BlockSpec& spec) {
  const auto t0 = Clock::now();
  const FootingModelSpec& fs = spec.footing;
  const Material& mat = fs.material;
  const double b = fs.half_width_m, vs = mat.vs();
  BlockResult out;
  out.equivalent_radius_m = 2.0 * b / std::sqrt(M_PI);  // same area
  const double r = out.equivalent_radius_m;
  const double mass_kg = spec.mass_ratio * 4.0 * mat.density_kg_m3 * r * r * r / (1.0 - mat.poisson_ratio);
  out.lysmer = lysmerAnalog(mat, r, mass_kg);
  const double pulse = spec.pulse_s > 0.0 ? spec.pulse_s : 0.1 / out.lysmer.natural_hz;
  const double duration = spec.duration_s > 0.0 ? spec.duration_s : 2.0 * (spec.box_m - b) / vs;
  Solver s(quarterBox(fs, spec.box_m), footingOptions(fs, FootingMode::Vertical, true));
  RigidBodySpec body = footingBody(fs, FootingMode::Vertical);
  // The quarter of the block: its mass minus that of the soil nodes the footing carries.
  double carried = 0.0;
  const size_t nb = static_cast<size_t>(std::llround(b / fs.h_m));
  for (size_t j = 0; j <= nb; ++j) {
    for (size_t i = 0; i <= nb; ++i) carried += s.nodalMass(s.mesh().node(i, j, 0));
  }
  body.added_mass(2, 2) = 0.25 * mass_kg - carried;
  if (body.added_mass(2, 2) <= 0.0) throw std::invalid_argument("ssi verification: block lighter than its soil");
  s.attachRigidBody(body);
  addFootingLoad(s, fs, FootingMode::Vertical);
  out.dt_s = s.dt();
  out.elements = s.mesh().elementCount();
  std::vector<double> force;
  while (s.time() < duration) {
    const double t = s.time();
    const double f = 1.0e4 * zeroImpulseWavelet(t, pulse);
    s.setChannelValues({f});
    s.step();
    out.t_s.push_back(s.time());
    out.displacement_m.push_back(s.rigidBody(0).displacement[2]);
    force.push_back(f);
  }
  out.steps = s.stepCount();
  // Free vibration after the pulse: zero crossings (linear interpolation) and the extremum between each pair
  // (parabolic refinement); kept while above 2 % of the first, where the weak reflections the dashpots let
  // back are still negligible.
  const std::vector<double>& u = out.displacement_m;
  std::vector<double> crossings, extrema;
  std::vector<size_t> at;
  for (size_t i = 1; i < u.size(); ++i) {
    if (out.t_s[i - 1] > pulse && (u[i - 1] < 0.0) != (u[i] < 0.0)) {
      const double f = u[i - 1] / (u[i - 1] - u[i]);
      crossings.push_back(out.t_s[i - 1] + f * (out.t_s[i] - out.t_s[i - 1]));
      at.push_back(i);
    }
  }
  for (size_t c = 0; c + 1 < at.size(); ++c) {
    size_t ip = at[c];
    for (size_t i = at[c]; i < at[c + 1]; ++i) {
      if (std::abs(u[i]) > std::abs(u[ip])) ip = i;
    }
    double v = std::abs(u[ip]);
    if (ip > 0 && ip + 1 < u.size()) {
      const double a = std::abs(u[ip - 1]), cc = std::abs(u[ip + 1]);
      const double d = a - 2.0 * v + cc;
      if (d < 0.0) v -= 0.125 * (a - cc) * (a - cc) / d;
    }
    if (!extrema.empty() && v < 0.02 * extrema.front()) break;
    extrema.push_back(v);
  }
  if (extrema.size() < 2) throw std::runtime_error("ssi verification: block run too short for a decrement");
  crossings.resize(extrema.size() + 1);
  out.damped_hz = 0.5 * static_cast<double>(crossings.size() - 1) / (crossings.back() - crossings.front());
  double half_decrement = 0.0;
  for (size_t k = 0; k + 1 < extrema.size(); ++k) half_decrement += std::log(extrema[k] / extrema[k + 1]);
  half_decrement /= static_cast<double>(extrema.size() - 1);
  const double delta = 2.0 * half_decrement;
  out.damping_ratio = delta / std::sqrt(4.0 * M_PI * M_PI + delta * delta);
  out.extrema_used = static_cast<int>(extrema.size());
  // Forced response: peak of |U / F| around the analog's natural frequency.
  double best = 0.0;
  const double dt = out.t_s[1] - out.t_s[0];
  for (double f = 0.3 * out.lysmer.natural_hz; f <= 2.0 * out.lysmer.natural_hz; f += 0.002 * out.lysmer.natural_hz) {
    const double w = 2.0 * M_PI * f;
    const double h = std::abs(fourier(out.t_s, u, w, dt) / fourier(out.t_s, force, w, dt));
    if (h > best) {
      best = h;
      out.resonance_hz = f;
    }
  }
  out.seconds = secondsSince(t0);
  return out;
}

// ---- Kinematic interaction of an embedded foundation ----

namespace {

// Node planes of `base` with one at `depth_m` (if none is within 1e-9 m): the layer band holding it is
// re-split on both sides with its own level thickness.
void planesWithDepth(const StructuredMesh& base, double depth_m, std::vector<double>& z, std::vector<Material>& mats) {
  size_t k = 0;
  while (k + 1 < base.nz && base.z[k + 1] < depth_m - 1e-9) ++k;
  const bool on_plane = std::abs(base.z[k + 1] - depth_m) < 1e-9;
  size_t lo = k, hi = k + 1;  // the band of levels [lo, hi) with the material of level k
  while (lo > 0 && base.level_material[lo - 1] == base.level_material[k]) --lo;
  while (hi < base.nz && base.level_material[hi] == base.level_material[k]) ++hi;
  z.assign(1, 0.0);
  mats.clear();
  for (size_t q = 0; q < base.nz; ++q) {
    if (on_plane || q != lo) {
      z.push_back(base.z[q + 1]);
      mats.push_back(base.levelMaterial(q));
      continue;
    }
    const double top = base.z[lo], bottom = base.z[hi], dz = base.z[lo + 1] - base.z[lo];
    const size_t n1 = static_cast<size_t>(std::ceil((depth_m - top) / dz - 1e-9));
    const size_t n2 = static_cast<size_t>(std::ceil((bottom - depth_m) / dz - 1e-9));
    for (size_t i = 1; i <= n1; ++i) z.push_back(top + (depth_m - top) * static_cast<double>(i) / n1);
    for (size_t i = 1; i <= n2; ++i) z.push_back(depth_m + (bottom - depth_m) * static_cast<double>(i) / n2);
    mats.insert(mats.end(), n1 + n2, base.levelMaterial(k));
    q = hi - 1;
  }
}

// 6 x 6 rigid-body mass R^T M R of the nodes in the box region about the reference point.
Eigen::Matrix<double, 6, 6> regionMass(const Solver& s, const RigidBodySpec& body, double& total_kg) {
  const StructuredMesh& m = s.mesh();
  Eigen::Matrix<double, 6, 6> mass = Eigen::Matrix<double, 6, 6>::Zero();
  total_kg = 0.0;
  const double tol = body.snap_tolerance_m;
  for (size_t k = 0; k <= m.nz && m.z[k] <= body.depth_m + tol; ++k) {
    for (size_t j = 0; j <= m.ny; ++j) {
      if (m.y(j) < body.y_min_m - tol || m.y(j) > body.y_max_m + tol) continue;
      for (size_t i = 0; i <= m.nx; ++i) {
        if (m.x(i) < body.x_min_m - tol || m.x(i) > body.x_max_m + tol) continue;
        const Eigen::Vector3d r = Eigen::Vector3d(m.x(i), m.y(j), m.z[k]) - body.reference_m;
        Eigen::Matrix<double, 3, 6> ra;
        ra.leftCols<3>().setIdentity();
        ra.rightCols<3>() << 0.0, r.z(), -r.y(), -r.z(), 0.0, r.x(), r.y(), -r.x(), 0.0;
        const double mn = s.nodalMass(m.node(i, j, k));
        mass += mn * ra.transpose() * ra;
        total_kg += mn;
      }
    }
  }
  return mass;
}

}  // namespace

KinematicResult runKinematic(const KinematicSpec& spec) {
  KinematicResult out;
  MeshSpec ms;
  ms.x_min_m = 0.0;
  ms.x_max_m = spec.x_max_m;
  ms.y_min_m = spec.y_min_m;
  ms.y_max_m = spec.y_max_m;
  ms.depth_m = spec.depth_m;
  ms.f_max_hz = spec.f_max_hz;
  ms.elements_per_wavelength = spec.elements_per_wavelength;
  const StructuredMesh base = buildMesh(spec.profile, ms);
  // In-plane grid with the foundation's edges on node lines (at most the target size).
  const double h = std::min(base.hx, base.hy);
  const double lx = spec.foundation_half_length_m, ly = spec.foundation_y_max_m - spec.foundation_y_min_m;
  const double hx = lx / std::ceil(lx / h - 1e-9), hy = ly / std::ceil(ly / h - 1e-9);
  const size_t nx = static_cast<size_t>(std::ceil(spec.x_max_m / hx - 1e-9));
  const size_t j_front = static_cast<size_t>(std::ceil((spec.foundation_y_min_m - spec.y_min_m) / hy - 1e-9));
  const double y0 = spec.foundation_y_min_m - hy * static_cast<double>(j_front);
  const size_t ny = static_cast<size_t>(std::ceil((spec.y_max_m - y0) / hy - 1e-9));
  std::vector<double> z;
  std::vector<Material> mats;
  planesWithDepth(base, spec.foundation_depth_m, z, mats);
  const StructuredMesh mesh = buildUniformMesh(nx, ny, hx, hy, z, mats, 0.0, y0);
  out.hx_m = hx;
  out.hy_m = hy;
  out.elements = mesh.elementCount();

  SolverOptions o = spec.solver;
  o.absorbing.x_min = false;
  o.symmetry_x_min = true;
  o.align_rate_hz = spec.output_rate_hz;

  RigidBodySpec body;
  body.name = "foundation";
  body.x_min_m = 0.0;
  body.x_max_m = spec.foundation_half_length_m;
  body.y_min_m = spec.foundation_y_min_m;
  body.y_max_m = spec.foundation_y_max_m;
  body.depth_m = spec.foundation_depth_m;
  body.snap_tolerance_m = 1e-6;
  const double yc = 0.5 * (spec.foundation_y_min_m + spec.foundation_y_max_m);
  body.reference_m = {0.0, yc, 0.0};
  // Symmetry plane x = 0: no sway along x, no turn about the y or vertical axes.
  body.held = {{true, false, false, false, true, true}};

  // Free field and foundation runs: vertical (down) velocity at the foundation's centre, and (free field)
  // its trapezoidal average over the footprint's surface nodes.
  auto run = [&](bool with_body, std::vector<double>& v_centre, std::vector<double>& v_footprint) {
    const auto t0 = Clock::now();
    Solver s(mesh, o);
    if (with_body) {
      double carried = 0.0;
      const Eigen::Matrix<double, 6, 6> soil_mass = regionMass(s, body, carried);
      RigidBodySpec b = body;
      b.added_mass = (spec.mass_fraction - 1.0) * soil_mass;
      s.attachRigidBody(b);
      out.carried_soil_mass_kg = s.rigidBody(0).carried_soil_mass_kg;
      out.body_mass_kg = spec.mass_fraction * carried;
      const RigidBodyState& st = s.rigidBody(0);
      out.x_max_m = st.x_max_m;
      out.y_min_m = st.y_min_m;
      out.y_max_m = st.y_max_m;
      out.depth_m = st.depth_m;
    }
    // Point load at (0, load_y): half of it in the half model, bilinear between the two nodes around load_y.
    const StructuredMesh& m = s.mesh();
    const double sy = (spec.load_y_m - m.y0) / m.hy;
    const size_t j = std::min(static_cast<size_t>(std::floor(sy)), m.ny - 1);
    const double fy = sy - static_cast<double>(j);
    ForceChannel ch;
    ch.nodes = {m.node(0, j, 0), m.node(0, j + 1, 0)};
    ch.components = {2, 2};
    ch.weights = {0.5 * (1.0 - fy), 0.5 * fy};
    s.addForceChannel(ch);
    std::vector<std::pair<size_t, double>> footprint;
    double wsum = 0.0;
    for (size_t jj = 0; jj <= m.ny; ++jj) {
      const double y = m.y(jj);
      if (y < body.y_min_m - 1e-6 || y > body.y_max_m + 1e-6) continue;
      const bool y_edge = y < body.y_min_m + 1e-6 || y > body.y_max_m - 1e-6;
      for (size_t i = 0; i <= m.nx && m.x(i) <= body.x_max_m + 1e-6; ++i) {
        const bool x_edge = i == 0 || m.x(i) > body.x_max_m - 1e-6;
        const double w = (y_edge ? 0.5 : 1.0) * (x_edge ? 0.5 : 1.0);
        footprint.emplace_back(m.node(i, jj, 0), w);
        wsum += w;
      }
    }
    const uint64_t steps = static_cast<uint64_t>(std::ceil(spec.duration_s / s.dt()));
    for (uint64_t n = 0; n < steps; ++n) {
      s.setChannelValues({1.0e4 * hannPulse(s.time(), spec.pulse_s)});
      s.step();
      double v[3];
      s.velocityAt(0.0, yc, 0.0, v);
      v_centre.push_back(v[2]);
      double avg = 0.0;
      for (const auto& [node, w] : footprint) avg += w * s.velocity(node, 2);
      v_footprint.push_back(avg / wsum);
      if (!std::isfinite(v[2])) throw std::runtime_error("ssi verification: kinematic run unstable");
    }
    out.dt_s = s.dt();
    out.steps = steps;
    return secondsSince(t0);
  };
  std::vector<double> v_ff, v_ff_avg, v_fd, v_fd_avg;
  out.seconds_free_field = run(false, v_ff, v_ff_avg);
  out.seconds_foundation = run(true, v_fd, v_fd_avg);

  auto tail = [](const std::vector<double>& v) {
    double all = 0.0, last = 0.0;
    for (size_t i = 0; i < v.size(); ++i) {
      all += v[i] * v[i];
      if (i >= v.size() - v.size() / 10) last += v[i] * v[i];
    }
    return last / all;
  };
  out.tail_energy_free_field = tail(v_ff);
  out.tail_energy_foundation = tail(v_fd);
  signal::DecimatorSpec ds;
  ds.input_rate_hz = std::round(1.0 / out.dt_s);
  ds.output_rate_hz = spec.output_rate_hz;
  out.v_free_field_m_s = signal::Decimator::decimate(v_ff, ds);
  out.v_foundation_m_s = signal::Decimator::decimate(v_fd, ds);
  out.v_free_field_footprint_m_s = signal::Decimator::decimate(v_ff_avg, ds);
  for (size_t k = 0; k < out.v_foundation_m_s.size(); ++k) {
    out.t_s.push_back(static_cast<double>(k) / spec.output_rate_hz);
  }
  // Band energies of the whole transient: zero padding lets the band filters ring down.
  auto padded = [&](std::vector<double> v) {
    v.resize(v.size() + static_cast<size_t>(spec.output_rate_hz), 0.0);
    return v;
  };
  const auto bands = signal::thirdOctaveBands(spec.band_min_hz, spec.band_max_hz, spec.output_rate_hz);
  const auto l_ff = signal::thirdOctaveLevels(padded(out.v_free_field_m_s), spec.output_rate_hz, bands);
  const auto l_fd = signal::thirdOctaveLevels(padded(out.v_foundation_m_s), spec.output_rate_hz, bands);
  const auto l_avg = signal::thirdOctaveLevels(padded(out.v_free_field_footprint_m_s), spec.output_rate_hz, bands);
  for (size_t i = 0; i < bands.size(); ++i) {
    KinematicBand kb;
    kb.nominal_hz = bands[i].nominal_hz;
    kb.level_free_field_db = l_ff[i];
    kb.level_foundation_db = l_fd[i];
    kb.ratio_centre = std::pow(10.0, (l_fd[i] - l_ff[i]) / 20.0);
    kb.ratio_footprint = std::pow(10.0, (l_fd[i] - l_avg[i]) / 20.0);
    out.bands.push_back(kb);
  }
  return out;
}

}  // namespace railvib::soil
