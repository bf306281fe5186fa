#include "railvib/soil/lamb.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "railvib/soil/solver.hpp"

namespace railvib::soil {

namespace {

// 8-point Gauss-Legendre on [-1, 1].
constexpr double kGx[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                           0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
constexpr double kGw[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                           0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

template <class F>
double gauss(F f, double a, double b, int panels) {
  double sum = 0.0;
  const double h = (b - a) / panels;
  for (int p = 0; p < panels; ++p) {
    const double c = a + (p + 0.5) * h;
    for (int q = 0; q < 8; ++q) sum += kGw[q] * f(c + 0.5 * h * kGx[q]);
  }
  return sum * 0.5 * h;
}

// Quarter model of a point load on the surface at the origin: symmetry on the
// x = 0 and y = 0 faces, Lysmer dashpots (and the given layer) on the others.
SolverOptions quarterModelOptions(Precision precision, const BoundarySpec& boundary) {
  SolverOptions o;
  o.absorbing.x_min = o.absorbing.y_min = false;
  o.symmetry_x_min = o.symmetry_y_min = true;
  o.precision = precision;
  o.boundary = boundary;
  return o;
}

// Force channel 0: the vertical point load at the origin (a quarter of it in the quarter model).
void addVerticalPointLoadAtOrigin(Solver& s) {
  ForceChannel ch;
  ch.nodes = {s.mesh().node(0, 0, 0)};
  ch.components = {2};
  ch.weights = {0.25};
  s.addForceChannel(ch);
}
}  // namespace

PekerisSolution::PekerisSolution(const Material& m) : mat_(m) {
  vs_ = m.vs();
  g_ = m.shearModulus();
  eta_ = vs_ / m.vp();
  tau_r_ = vs_ / m.vr();
}

double PekerisSolution::staticValue() const { return (1.0 - mat_.poisson_ratio) / (2.0 * M_PI); }

double PekerisSolution::denominator(double s) const {
  const double e2 = eta_ * eta_;
  return 1.0 - 8.0 * s + 8.0 * (3.0 - 2.0 * e2) * s * s - 16.0 * (1.0 - e2) * s * s * s;
}

double PekerisSolution::denominatorSlope(double s) const {
  const double e2 = eta_ * eta_;
  return -8.0 + 16.0 * (3.0 - 2.0 * e2) * s - 48.0 * (1.0 - e2) * s * s;
}

double PekerisSolution::stepNormalised(double tau) const {
  if (tau <= eta_) return 0.0;
  const double e2 = eta_ * eta_, t2 = tau * tau, sr = tau_r_ * tau_r_;
  // I(lo2, num): integral over theta in [0, pi/2] of num(s) sin^2(theta) / D(s), s = lo2 + (t2 - lo2) sin^2(theta),
  // as a principal value when the Rayleigh pole s = tau_R^2 lies inside (tau > tau_R): singularity subtraction.
  auto integral = [&](double lo2, auto num) {
    auto g = [&](double th) {
      const double sn = std::sin(th);
      const double s = lo2 + (t2 - lo2) * sn * sn;
      return num(s) * sn * sn / denominator(s);
    };
    if (tau <= tau_r_) return gauss(g, 0.0, 0.5 * M_PI, 64);
    const double th_r = std::asin(std::sqrt((sr - lo2) / (t2 - lo2)));
    // Near th_r: D(s(th)) ~ D'(s_R) ds/dth (th - th_r); residue coefficient c.
    const double sn = std::sin(th_r), cs = std::cos(th_r);
    const double dsdth = (t2 - lo2) * 2.0 * sn * cs;
    const double c = num(sr) * sn * sn / (denominatorSlope(sr) * dsdth);
    auto smooth = [&](double th) { return g(th) - c / (th - th_r); };
    const double body = gauss(smooth, 0.0, th_r, 64) + gauss(smooth, th_r, 0.5 * M_PI, 64);
    return body + c * std::log((0.5 * M_PI - th_r) / th_r);
  };
  double g1 = (t2 - e2) * integral(e2, [](double s) { return (1.0 - 2.0 * s) * (1.0 - 2.0 * s); });
  double g2 = 0.0;
  if (tau > 1.0) g2 = 4.0 * (t2 - 1.0) * integral(1.0, [e2](double s) { return s * (s - e2); });
  // Sign: positive in the direction of the load (the static limit, reached after tau_R, is positive).
  return -(g1 + g2) / (M_PI * M_PI);
}

double PekerisSolution::stepDisplacement(double p_n, double r_m, double t_s) const {
  return stepNormalised(vs_ * t_s / r_m) * p_n / (g_ * r_m);
}

std::vector<double> PekerisSolution::smoothStepResponse(double p_n, double r_m, double rise_s,
                                                        const std::vector<double>& t_s) const {
  return response(p_n, r_m, rise_s, t_s, false);
}

std::vector<double> PekerisSolution::hannPulseResponse(double p_n, double r_m, double duration_s,
                                                       const std::vector<double>& t_s) const {
  return response(p_n, r_m, duration_s, t_s, true);
}

std::vector<double> PekerisSolution::response(double p_n, double r_m, double rise_s, const std::vector<double>& t_s,
                                              bool pulse) const {
  // w(t) = int U1(t - s) S''(s) ds with U1 the time integral of the step response
  // (continuous although the step response is singular at the Rayleigh arrival).
  const double t_max = *std::max_element(t_s.begin(), t_s.end());
  const double tau_max = vs_ * t_max / r_m + 1e-9;
  // Grid in tau: uniform plus geometric clustering on both sides of tau_R.
  std::vector<double> taus;
  const int nu = 4000;
  for (int i = 0; i <= nu; ++i) taus.push_back(eta_ + (tau_max - eta_) * i / nu);
  for (double d = 1e-9; d < 0.05; d *= 1.3) {
    taus.push_back(tau_r_ - d);
    taus.push_back(tau_r_ + d);
  }
  taus.push_back(0.0);
  std::sort(taus.begin(), taus.end());
  taus.erase(std::remove_if(taus.begin(), taus.end(), [&](double x) { return x > tau_max || x < 0.0; }), taus.end());
  std::vector<double> w(taus.size()), u1(taus.size(), 0.0);
  for (size_t i = 0; i < taus.size(); ++i) w[i] = stepNormalised(taus[i]);
  for (size_t i = 1; i < taus.size(); ++i) {
    // Do not evaluate the singular endpoint weight at tau_R: trapezoid on the clustered grid.
    u1[i] = u1[i - 1] + 0.5 * (w[i] + w[i - 1]) * (taus[i] - taus[i - 1]);
  }
  auto U1 = [&](double t) {  // in tau units * (r / Vs) * P / (G r)
    const double tau = vs_ * t / r_m;
    if (tau <= taus.front()) return 0.0;
    if (tau >= taus.back()) return u1.back();
    const size_t k = static_cast<size_t>(std::upper_bound(taus.begin(), taus.end(), tau) - taus.begin());
    const double f = (tau - taus[k - 1]) / (taus[k] - taus[k - 1]);
    return (u1[k - 1] + f * (u1[k] - u1[k - 1])) * (r_m / vs_) * p_n / (g_ * r_m);
  };
  std::vector<double> out;
  for (double t : t_s) {
    const double k = (pulse ? 2.0 : 1.0) * M_PI / rise_s;  // S'' = k^2 / 2 cos(k s) on [0, rise]
    auto f = [&](double s) { return U1(t - s) * 0.5 * k * k * std::cos(k * s); };
    out.push_back(gauss(f, 0.0, rise_s, 200));
  }
  return out;
}

LambResult runLamb(const LambSpec& spec) {
  const size_t n = static_cast<size_t>(std::llround(spec.half_width_m / spec.h_m));
  const size_t nz = static_cast<size_t>(std::llround(spec.depth_m / spec.h_m));
  std::vector<double> z(nz + 1);
  for (size_t k = 0; k <= nz; ++k) z[k] = spec.h_m * static_cast<double>(k);
  SolverOptions o = quarterModelOptions(spec.precision, spec.boundary);
  o.kernel = spec.kernel;
  Solver s(buildUniformMesh(n, n, spec.h_m, spec.h_m, z, std::vector<Material>(nz, spec.material)), o);
  addVerticalPointLoadAtOrigin(s);
  const double rmax = *std::max_element(spec.distances_m.begin(), spec.distances_m.end());
  const double t_end =
      spec.duration_s > 0.0 ? spec.duration_s : rmax / spec.material.vr() + (spec.pulse ? 1.0 : 1.5) * spec.rise_s;
  LambResult res;
  res.dt_s = s.dt();
  res.elements = s.mesh().elementCount();
  res.w_fe.assign(spec.distances_m.size(), {});
  std::vector<double> val(1);
  while (s.time() < t_end) {
    const double t = s.time();
    if (spec.pulse) {
      val[0] = spec.load_n * (t >= spec.rise_s ? 0.0 : 0.5 * (1.0 - std::cos(2.0 * M_PI * t / spec.rise_s)));
    } else {
      val[0] = spec.load_n * (t >= spec.rise_s ? 1.0 : 0.5 * (1.0 - std::cos(M_PI * t / spec.rise_s)));
    }
    s.setChannelValues(val);
    s.step();
    res.t_s.push_back(s.time());
    for (size_t r = 0; r < spec.distances_m.size(); ++r) {
      double u[3];
      s.displacementAt(spec.distances_m[r], 0.0, 0.0, u);
      res.w_fe[r].push_back(u[2]);
    }
  }
  const PekerisSolution an(spec.material);
  for (size_t r = 0; r < spec.distances_m.size(); ++r) {
    res.w_an.push_back(spec.pulse ? an.hannPulseResponse(spec.load_n, spec.distances_m[r], spec.rise_s, res.t_s)
                                  : an.smoothStepResponse(spec.load_n, spec.distances_m[r], spec.rise_s, res.t_s));
    LambStation st;
    st.r_m = spec.distances_m[r];
    auto features = [&](const std::vector<double>& w, double& t_p, double& t_r, double& peak) {
      peak = 0.0;
      size_t ip = 0;
      for (size_t i = 0; i < w.size(); ++i) {
        if (std::abs(w[i]) > peak) {
          peak = std::abs(w[i]);
          ip = i;
        }
      }
      const double dt = res.t_s[1] - res.t_s[0];
      t_r = res.t_s[ip];
      if (ip > 0 && ip + 1 < w.size()) {
        const double a = std::abs(w[ip - 1]), b = std::abs(w[ip]), c = std::abs(w[ip + 1]);
        const double d = a - 2 * b + c;
        if (d != 0.0) t_r += 0.5 * (a - c) / d * dt;
      }
      t_p = res.t_s.back();
      const double thr = 0.02 * peak;
      for (size_t i = 1; i < w.size(); ++i) {
        if (std::abs(w[i]) > thr) {
          const double a = std::abs(w[i - 1]), b = std::abs(w[i]);
          t_p = res.t_s[i - 1] + (thr - a) / (b - a) * dt;
          break;
        }
      }
    };
    features(res.w_fe[r], st.t_p_fe_s, st.t_r_fe_s, st.peak_fe_m);
    features(res.w_an[r], st.t_p_an_s, st.t_r_an_s, st.peak_an_m);
    st.elements_per_rayleigh_wavelength = spec.material.vr() * spec.rise_s / spec.h_m;
    res.stations.push_back(st);
  }
  return res;
}

ReflectionRow reflectionFigures(const std::vector<double>& w, const std::vector<double>& w_ref, double dt_s) {
  ReflectionRow row;
  const size_t n = std::min(w.size(), w_ref.size());
  double dmax = 0.0, ref_max = 0.0;
  for (size_t i = 0; i < n; ++i) {
    dmax = std::max(dmax, std::abs(w[i] - w_ref[i]));
    ref_max = std::max(ref_max, std::abs(w_ref[i]));
  }
  row.peak = dmax / ref_max;
  // |Fourier transform|^2 of the difference and of the reference on 1 Hz lines.
  auto band = [&](double f0, double f1) {
    double ed = 0.0, er = 0.0;
    for (double f = f0; f <= f1 + 1e-9; f += 1.0) {
      const double dphi = 2.0 * M_PI * f * dt_s;
      const double c1 = std::cos(dphi), s1 = std::sin(dphi);
      double c = 1.0, s = 0.0, dr = 0.0, di = 0.0, rr = 0.0, ri = 0.0;
      for (size_t i = 0; i < n; ++i) {
        const double d = w[i] - w_ref[i];
        dr += d * c;
        di -= d * s;
        rr += w_ref[i] * c;
        ri -= w_ref[i] * s;
        const double cn = c * c1 - s * s1;
        s = s * c1 + c * s1;
        c = cn;
      }
      ed += dr * dr + di * di;
      er += rr * rr + ri * ri;
    }
    return std::sqrt(ed / er);
  };
  row.band_10_50 = band(10.0, 50.0);
  row.band_10_20 = band(10.0, 20.0);
  row.band_20_35 = band(21.0, 35.0);
  row.band_35_50 = band(36.0, 50.0);
  row.band_21_30 = band(21.0, 30.0);
  row.band_31_40 = band(31.0, 40.0);
  row.band_41_50 = band(41.0, 50.0);
  return row;
}

ReflectionCase ReflectionCase::gradedLayer(double thickness_m, double max_alpha_1_s, double exponent, bool bottom) {
  ReflectionCase c;
  c.layer_m = thickness_m;
  c.bottom = bottom;
  if (thickness_m > 0.0 && max_alpha_1_s > 0.0) {
    c.boundary.method = BoundaryMethod::GradedLayer;
    c.boundary.graded_layer = {thickness_m, max_alpha_1_s, exponent, bottom};
  }
  return c;
}

ReflectionCase ReflectionCase::pml(const PmlSpec& spec) {
  ReflectionCase c;
  c.layer_m = spec.thickness_m;
  c.bottom = spec.bottom;
  c.boundary.method = BoundaryMethod::Pml;
  c.boundary.pml = spec;
  return c;
}

ReflectionResult runBoundaryReflection(double small_half_width_m, const std::vector<ReflectionCase>& cases) {
  ReflectionResult out;
  LambSpec ref;
  ref.distances_m = {6.0};
  ref.half_width_m = 2.5 * small_half_width_m;
  ref.depth_m = 2.5 * small_half_width_m;
  // Window: until the Rayleigh pulse reflected by the reference box's side could come back.
  out.r_m = 6.0;
  out.window_s = (2.0 * ref.half_width_m - out.r_m) / ref.material.vr();
  ref.duration_s = out.window_s;
  const LambResult a = runLamb(ref);
  out.reference_elements = a.elements;
  for (const ReflectionCase& c : cases) {
    LambSpec small = ref;
    small.half_width_m = small_half_width_m + c.layer_m;
    small.depth_m = small_half_width_m + (c.bottom ? c.layer_m : 0.0);
    if (small.half_width_m >= ref.half_width_m) {
      throw std::invalid_argument("soil reflection: box with the layer too large for the reference box");
    }
    small.boundary = c.boundary;
    const LambResult r = runLamb(small);
    ReflectionRow row = reflectionFigures(r.w_fe[0], a.w_fe[0], a.dt_s);
    if (r.dt_s != a.dt_s) throw std::logic_error("soil reflection: small and reference boxes must share dt");
    row.absorber = c;
    row.elements = r.elements;
    row.dt_s = r.dt_s;
    out.rows.push_back(row);
  }
  return out;
}

namespace {

struct LayeredRun {
  std::vector<std::vector<double>> w;  // per station
  double dt_s = 0.0;
  size_t elements = 0;
};

LayeredRun layeredRun(const LayeredReflectionSpec& spec, const StructuredMesh& base, double half_width_m,
                      double depth_m, const BoundarySpec& boundary) {
  const size_t n = static_cast<size_t>(std::llround(half_width_m / base.hx));
  std::vector<double> z(base.z);
  std::vector<Material> mats;
  for (size_t k = 0; k < base.nz; ++k) mats.push_back(base.levelMaterial(k));
  const double dz = z[base.nz] - z[base.nz - 1];
  while (z.back() < depth_m - 0.5 * dz) {
    z.push_back(z.back() + dz);
    mats.push_back(mats.back());
  }
  SolverOptions o = quarterModelOptions(spec.precision, boundary);
  o.rayleigh_beta_s = spec.rayleigh_beta_s;
  o.damping_cutoff_hz = spec.damping_cutoff_hz;
  Solver s(buildUniformMesh(n, n, base.hx, base.hx, z, mats), o);
  addVerticalPointLoadAtOrigin(s);
  LayeredRun run;
  run.dt_s = s.dt();
  run.elements = s.mesh().elementCount();
  run.w.assign(spec.distances_m.size(), {});
  std::vector<double> val(1);
  while (s.time() < spec.window_s) {
    const double t = s.time();
    val[0] = 1.0e4 * (t >= spec.pulse_s ? 0.0 : 0.5 * (1.0 - std::cos(2.0 * M_PI * t / spec.pulse_s)));
    s.setChannelValues(val);
    s.step();
    for (size_t r = 0; r < spec.distances_m.size(); ++r) {
      double u[3];
      s.displacementAt(spec.distances_m[r], 0.0, 0.0, u);
      run.w[r].push_back(u[2]);
    }
  }
  return run;
}

}  // namespace

LayeredReflectionResult runLayeredReflection(const LayeredReflectionSpec& spec,
                                             const std::vector<ReflectionCase>& cases) {
  MeshSpec ms;
  ms.x_min_m = ms.y_min_m = 0.0;
  ms.x_max_m = ms.y_max_m = spec.box_half_width_m;
  ms.depth_m = spec.box_depth_m;
  ms.f_max_hz = spec.f_max_hz;
  ms.elements_per_wavelength = spec.elements_per_wavelength;
  const StructuredMesh base = buildMesh(spec.profile, ms);
  LayeredReflectionResult out;
  out.h_m = base.hx;
  const LayeredRun ref = layeredRun(spec, base, spec.reference_half_width_m, spec.reference_depth_m, BoundarySpec{});
  out.dt_s = ref.dt_s;
  out.reference_elements = ref.elements;
  for (const ReflectionCase& c : cases) {
    const double w = spec.box_half_width_m + c.layer_m;
    const double d = spec.box_depth_m + (c.bottom ? c.layer_m : 0.0);
    if (w >= spec.reference_half_width_m || d >= spec.reference_depth_m) {
      throw std::invalid_argument("soil reflection: box with the layer too large for the reference box");
    }
    const LayeredRun r = layeredRun(spec, base, w, d, c.boundary);
    if (r.dt_s != ref.dt_s) throw std::logic_error("soil reflection: boxes must share dt");
    LayeredReflectionRow row;
    row.absorber = c;
    row.elements = r.elements;
    for (size_t k = 0; k < spec.distances_m.size(); ++k) {
      row.stations.push_back(reflectionFigures(r.w[k], ref.w[k], ref.dt_s));
    }
    out.rows.push_back(row);
  }
  return out;
}

}  // namespace railvib::soil
