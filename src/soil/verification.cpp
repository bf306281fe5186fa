#include "railvib/soil/verification.hpp"

#include <omp.h>
#include <sys/resource.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "railvib/common/force_inline.hpp"

namespace railvib::soil {

namespace {

double hannStep(double t, double rise) {
  if (t <= 0.0) return 0.0;
  if (t >= rise) return 1.0;
  return 0.5 * (1.0 - std::cos(M_PI * t / rise));
}

double hannPulse(double t, double duration) {
  if (t <= 0.0 || t >= duration) return 0.0;
  return 0.5 * (1.0 - std::cos(2.0 * M_PI * t / duration));
}

struct ColumnRun {
  std::vector<double> t, v;
  double dt = 0.0;
  size_t elements = 0;
};

ColumnRun columnRun(const ColumnSpec& s, bool pulse, double t_end) {
  const size_t nz = static_cast<size_t>(std::llround(s.length_m / s.dz_m));
  std::vector<double> z(nz + 1);
  for (size_t k = 0; k <= nz; ++k) z[k] = s.dz_m * static_cast<double>(k);
  StructuredMesh mesh = buildUniformMesh(1, 1, s.dz_m, s.dz_m, z, std::vector<Material>(nz, s.material));
  SolverOptions o;
  o.absorbing.x_min = o.absorbing.x_max = o.absorbing.y_min = o.absorbing.y_max = false;
  o.absorbing.bottom = true;
  o.lateral_rollers = true;
  o.precision = s.precision;
  o.kernel = s.kernel;
  o.threads = 1;
  Solver solver(std::move(mesh), o);
  const auto& m = solver.mesh();
  ForceChannel top;
  for (size_t c = 0; c < 4; ++c) {
    top.nodes.push_back(m.node(c & 1, (c >> 1) & 1, 0));
    top.components.push_back(2);
    top.weights.push_back(m.hx * m.hy / 4.0);
  }
  solver.addForceChannel(top);
  ColumnRun run;
  run.dt = solver.dt();
  run.elements = m.elementCount();
  std::vector<double> val(1);
  while (solver.time() < t_end) {
    const double t = solver.time();
    val[0] = s.pressure_pa * (pulse ? hannPulse(t, s.rise_s) : hannStep(t, s.rise_s));
    solver.setChannelValues(val);
    solver.step();
    double vel[3];
    solver.velocityAt(0.5 * m.hx, 0.5 * m.hy, s.receiver_depth_m, vel);
    run.t.push_back(solver.time() - 0.5 * solver.dt());
    run.v.push_back(vel[2]);
  }
  return run;
}

double meanOver(const ColumnRun& r, double a, double b) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] >= a && r.t[i] <= b) {
      sum += r.v[i];
      ++n;
    }
  }
  if (n == 0) throw std::logic_error("column: empty averaging window");
  return sum / static_cast<double>(n);
}

double maxAbsOver(const ColumnRun& r, double a, double b) {
  double m = 0.0;
  for (size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] >= a && r.t[i] <= b) m = std::max(m, std::abs(r.v[i]));
  }
  return m;
}

}  // namespace

ColumnResult runColumn(const ColumnSpec& s) {
  ColumnResult res;
  const double vp = s.material.vp();
  res.expected_velocity_m_s = s.pressure_pa / (s.material.density_kg_m3 * vp);
  const double t_arrival = s.receiver_depth_m / vp;
  const double t_reflect = (2.0 * s.length_m - s.receiver_depth_m) / vp;
  // Step: plateau between the incident front and the reflection; then after it.
  {
    const double t_end = t_reflect + 3.0 * s.rise_s + 0.25 * (t_reflect - t_arrival);
    const ColumnRun r = columnRun(s, false, t_end);
    res.dt_s = r.dt;
    res.elements = r.elements;
    res.incident_velocity_m_s = meanOver(r, t_arrival + 2.0 * s.rise_s, t_reflect - s.rise_s);
    res.after_velocity_m_s = meanOver(r, t_reflect + 3.0 * s.rise_s, t_end);
    res.velocity_error = res.incident_velocity_m_s / res.expected_velocity_m_s - 1.0;
    res.step_reflection = (res.after_velocity_m_s - res.incident_velocity_m_s) / res.incident_velocity_m_s;
  }
  // Pulse: incident peak, then the largest |v| when the reflection would pass.
  {
    const double t_end = t_reflect + 3.0 * s.rise_s;
    const ColumnRun r = columnRun(s, true, t_end);
    res.pulse_incident_peak_m_s = maxAbsOver(r, 0.0, t_arrival + 3.0 * s.rise_s);
    res.pulse_reflected_peak_m_s = maxAbsOver(r, t_reflect - 0.5 * s.rise_s, t_end);
    res.pulse_reflection = res.pulse_reflected_peak_m_s / res.pulse_incident_peak_m_s;
  }
  return res;
}

namespace {
// Lowest non-rigid mode of a free 2x2x2 box of unit element size: eigenvalue and M-normalised shape.
void lowestFreeMode(const Material& mat, double h, double& lambda, std::vector<double>& shape) {
  std::vector<double> z = {0.0, h, 2.0 * h};
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};
  o.precision = Precision::Double;
  o.threads = 1;
  Solver probe(buildUniformMesh(2, 2, h, h, z, {mat, mat}), o);
  const size_t n = probe.mesh().nodeCount(), ndof = 3 * n;
  Eigen::MatrixXd a(ndof, ndof);
  std::vector<double> f;
  for (size_t q = 0; q < ndof; ++q) {
    probe.setDisplacement(q / 3, static_cast<int>(q % 3), 1.0);
    probe.internalForce(f);
    probe.setDisplacement(q / 3, static_cast<int>(q % 3), 0.0);
    for (size_t r = 0; r < ndof; ++r) {
      a(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(q)) =
          -f[r] / std::sqrt(probe.nodalMass(r / 3) * probe.nodalMass(q / 3));
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (a + a.transpose()));
  const double top = es.eigenvalues().maxCoeff();
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) {
    if (es.eigenvalues()(i) > 1e-8 * top) {
      lambda = es.eigenvalues()(i);
      shape.resize(ndof);
      for (size_t r = 0; r < ndof; ++r) {
        shape[r] = es.eigenvectors()(static_cast<Eigen::Index>(r), i) / std::sqrt(probe.nodalMass(r / 3));
      }
      return;
    }
  }
  throw std::logic_error("no elastic mode found");
}
}  // namespace

DampingDecayResult runDampingDecay(double f_hz, double beta_s, double cutoff_hz, Precision precision) {
  const Material mat{61.0e6, 1876.0, 0.13};
  double lambda1 = 0.0;
  std::vector<double> shape;
  lowestFreeMode(mat, 1.0, lambda1, shape);
  const double f1 = std::sqrt(lambda1) / (2.0 * M_PI);
  const double h = f1 / f_hz;  // frequencies scale as 1 / h
  std::vector<double> z = {0.0, h, 2.0 * h};
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};
  o.rayleigh_beta_s = beta_s;
  o.damping_cutoff_hz = cutoff_hz;
  o.precision = precision;
  o.threads = 1;
  const double period = 1.0 / f_hz;
  {
    Solver tmp(buildUniformMesh(2, 2, h, h, z, {mat, mat}), o);
    if (tmp.dt() > period / 20.0) o.dt_s = period / 20.0;
  }
  Solver s(buildUniformMesh(2, 2, h, h, z, {mat, mat}), o);
  const size_t n = s.mesh().nodeCount();
  // Mode shapes are geometry-invariant; the M-normalisation scales with h^(3/2): only the shape matters here.
  for (size_t q = 0; q < 3 * n; ++q) s.setDisplacement(q / 3, static_cast<int>(q % 3), 1e-3 * shape[q]);
  auto modal = [&]() {
    double acc = 0.0;
    for (size_t q = 0; q < 3 * n; ++q)
      acc += shape[q] * s.nodalMass(q / 3) * s.displacement(q / 3, static_cast<int>(q % 3));
    return acc;
  };
  const double target = beta_s * 2.0 * M_PI * f_hz / 2.0;
  // Run about 1.5 / (target omega) seconds (amplitude falls to ~e^-1.5), at least 20 periods.
  const double t_end = std::max(20.0 * period, 1.5 / (target * 2.0 * M_PI * f_hz));
  std::vector<double> q, t;
  q.push_back(modal());
  t.push_back(0.0);
  while (s.time() < t_end) {
    s.step();
    q.push_back(modal());
    t.push_back(s.time());
  }
  // Positive peaks with parabolic refinement; least-squares slope of ln(peak).
  std::vector<double> pt, pl;
  std::vector<double> crossings;
  for (size_t i = 1; i + 1 < q.size(); ++i) {
    if (q[i] > q[i - 1] && q[i] >= q[i + 1] && q[i] > 0.0) {
      const double d = q[i - 1] - 2 * q[i] + q[i + 1];
      const double off = d != 0.0 ? 0.5 * (q[i - 1] - q[i + 1]) / d : 0.0;
      const double peak = q[i] - 0.25 * (q[i - 1] - q[i + 1]) * off;
      pt.push_back(t[i] + off * s.dt());
      pl.push_back(std::log(peak));
    }
    if (q[i] <= 0.0 && q[i + 1] > 0.0) crossings.push_back(t[i] + s.dt() * q[i] / (q[i] - q[i + 1]));
  }
  if (pt.size() < 3 || crossings.size() < 2) throw std::logic_error("damping decay: too few peaks");
  double st = 0, sl = 0, stt = 0, stl = 0;
  const double np = static_cast<double>(pt.size());
  for (size_t i = 0; i < pt.size(); ++i) {
    st += pt[i];
    sl += pl[i];
    stt += pt[i] * pt[i];
    stl += pt[i] * pl[i];
  }
  const double slope = (np * stl - st * sl) / (np * stt - st * st);
  DampingDecayResult r;
  r.frequency_hz = static_cast<double>(crossings.size() - 1) / (crossings.back() - crossings.front());
  r.measured_ratio = -slope / (2.0 * M_PI * r.frequency_hz);
  r.target_ratio = beta_s * 2.0 * M_PI * r.frequency_hz / 2.0;
  r.dt_s = s.dt();
  r.dt_undamped_s = s.dtUndamped();
  r.dt_naive_s = s.dtNaiveRayleigh();
  return r;
}

namespace {

double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
}

double medianOf(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A kernel of the solver's kind, mesh, box and threads on its own random fields: the kernel without the step.
struct KernelTimer {
  virtual ~KernelTimer() = default;
  virtual double secondsFor(int applications) = 0;
  virtual double multiplyAdds() const = 0;
};

template <class Real>
struct KernelTimerT final : KernelTimer {
  KernelTimerT(const Solver& s, KernelKind kind, int threads)
      : kernel(makeStiffnessKernel<Real>(kind, s.mesh(), s.kernelElements(), threads)) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<Real> dist(-1e-4, 1e-4);
    for (int c = 0; c < 3; ++c) {
      w[c].resize(s.mesh().nodeCount());
      for (Real& x : w[c]) x = dist(rng);
      f[c].assign(s.mesh().nodeCount(), 0);
    }
  }
  double secondsFor(int applications) override {
    const Real* in[3] = {w[0].data(), w[1].data(), w[2].data()};
    Real* out[3] = {f[0].data(), f[1].data(), f[2].data()};
    const double t0 = omp_get_wtime();
    for (int a = 0; a < applications; ++a) kernel->apply(in, out);
    return omp_get_wtime() - t0;
  }
  double multiplyAdds() const override { return kernel->multiplyAddsPerApply(); }
  std::unique_ptr<StiffnessKernel<Real>> kernel;
  std::vector<Real> w[3], f[3];
};

}  // namespace

std::vector<ThroughputResult> runThroughput(const ThroughputSpec& spec) {
  if (spec.kernels.empty() || spec.steps < 1 || spec.repeat < 1)
    throw std::invalid_argument("throughput: nothing to run");
  const Material mat{61.0e6, 1876.0, 0.13};
  const double h = 0.3;
  std::vector<double> z(spec.nz + 1);
  for (size_t k = 0; k <= spec.nz; ++k) z[k] = h * static_cast<double>(k);
  const StructuredMesh mesh = buildUniformMesh(spec.nx, spec.ny, h, h, z, std::vector<Material>(spec.nz, mat));
  std::vector<std::unique_ptr<Solver>> solvers;
  std::vector<std::unique_ptr<KernelTimer>> timers;
  for (KernelKind kind : spec.kernels) {
    SolverOptions o;
    o.precision = spec.precision;
    o.threads = spec.threads;
    o.rayleigh_beta_s = 4e-4;
    o.kernel = kind;
    o.boundary = spec.boundary;
    solvers.push_back(std::make_unique<Solver>(mesh, o));
    Solver& s = *solvers.back();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> dist(-1e-4, 1e-4);
    for (size_t i = 0; i < s.mesh().nodeCount(); i += 7) s.setDisplacement(i, static_cast<int>(i % 3), dist(rng));
    s.run(2);
    if (spec.precision == Precision::Float) {
      timers.push_back(std::make_unique<KernelTimerT<float>>(s, kind, spec.threads));
    } else {
      timers.push_back(std::make_unique<KernelTimerT<double>>(s, kind, spec.threads));
    }
    timers.back()->secondsFor(2);
  }
  const size_t nk = spec.kernels.size();
  const double updates = static_cast<double>(mesh.elementCount()) * spec.steps;
  std::vector<std::vector<double>> rate(nk), cpu_rate(nk), step_s(nk), kernel_s(nk), step_ratio(nk), kernel_ratio(nk),
      step_cpu_s(nk), kernel_cpu_s(nk);
  for (int rep = 0; rep < spec.repeat; ++rep) {
    // The kernels in turn, so that each repeat compares them at the same load of the machine.
    for (size_t q = 0; q < nk; ++q) {
      const double c0 = cpuSeconds(), t0 = omp_get_wtime();
      solvers[q]->run(static_cast<uint64_t>(spec.steps));
      const double el = omp_get_wtime() - t0, cpu_s = cpuSeconds() - c0;
      const double kc0 = cpuSeconds();
      const double kern = timers[q]->secondsFor(spec.steps);
      kernel_cpu_s[q].push_back((cpuSeconds() - kc0) / spec.steps);
      step_cpu_s[q].push_back(cpu_s / spec.steps);
      rate[q].push_back(updates / el);
      cpu_rate[q].push_back(updates / cpu_s);
      step_s[q].push_back(el / spec.steps);
      kernel_s[q].push_back(kern / spec.steps);
      step_ratio[q].push_back(step_s[0].back() / step_s[q].back());
      kernel_ratio[q].push_back(kernel_s[0].back() / kernel_s[q].back());
    }
  }
  std::vector<ThroughputResult> out;
  for (size_t q = 0; q < nk; ++q) {
    ThroughputResult r;
    r.kernel = spec.kernels[q];
    r.elements = mesh.elementCount();
    r.boundary_elements = r.elements - solvers[q]->kernelElements().count();
    r.threads = spec.threads;
    r.element_updates_per_s = medianOf(rate[q]);
    r.element_updates_per_cpu_s = medianOf(cpu_rate[q]);
    r.min_element_updates_per_s = *std::min_element(rate[q].begin(), rate[q].end());
    r.max_element_updates_per_s = *std::max_element(rate[q].begin(), rate[q].end());
    r.seconds_per_step = medianOf(step_s[q]);
    r.kernel_seconds_per_apply = medianOf(kernel_s[q]);
    r.cpu_seconds_per_step = medianOf(step_cpu_s[q]);
    r.kernel_cpu_seconds_per_apply = medianOf(kernel_cpu_s[q]);
    r.kernel_element_updates_per_s = static_cast<double>(mesh.elementCount()) / r.kernel_seconds_per_apply;
    r.multiply_adds_per_step = timers[q]->multiplyAdds();
    r.kernel_gflop_s = 2.0 * r.multiply_adds_per_step / r.kernel_seconds_per_apply * 1e-9;
    r.step_ratio_to_first = medianOf(step_ratio[q]);
    r.kernel_ratio_to_first = medianOf(kernel_ratio[q]);
    out.push_back(r);
  }
  return out;
}

namespace {
// A surface point load in the middle of the box, on the nodes this rank owns (the channel is global).
void addCentreLoad(Solver& s) {
  const StructuredMesh& m = s.mesh();
  ForceChannel ch;
  for (size_t j = m.ny / 2 - 1; j <= m.ny / 2 + 1; ++j) {
    for (size_t i = m.nx / 2 - 1; i <= m.nx / 2 + 1; ++i) {
      ch.nodes.push_back(m.node(i, j, 0));
      ch.components.push_back(2);
      ch.weights.push_back(1.0 / 9.0);
    }
  }
  s.addForceChannel(ch);
}

void drive(Solver& s, int steps) {
  for (int n = 0; n < steps; ++n) {
    const double t = s.time();
    s.setChannelValues({1.0e4 * std::sin(2.0 * M_PI * 30.0 * t)});
    s.step();
  }
}
}  // namespace

RankScalingResult runRankScaling(const RankScalingSpec& spec, const std::shared_ptr<SoilComm>& comm) {
  if (spec.steps < 1 || spec.repeat < 1) throw std::invalid_argument("rank scaling: nothing to run");
  SolverOptions o = spec.options;
  o.ranks = 0;
  std::unique_ptr<Solver> one;
  if (comm->root()) {
    one = std::make_unique<Solver>(spec.mesh, o, serialSoilComm());
    addCentreLoad(*one);
    drive(*one, 2);
  }
  Solver spread(spec.mesh, o, comm);
  addCentreLoad(spread);
  drive(spread, 2);
  // Each rank's slab alone, as a mesh of its own (no neighbour, no exchange, the cut faces left free
  // as in the spread run), all ranks at once: what the machine gives to independent work of the same
  // size, i.e. the ceiling of the spread run's speed-up on this machine.
  std::unique_ptr<Solver> alone;
  if (comm->size() > 1) {
    const SlabPartition& part = spread.partition();
    SolverOptions oa = o;
    if (part.hasLow()) oa.absorbing.x_min = oa.symmetry_x_min = oa.antisymmetry_x_min = false;
    if (part.hasHigh()) oa.absorbing.x_max = false;
    alone = std::make_unique<Solver>(sliceMesh(spec.mesh, part.begin(), part.end()), oa, serialSoilComm());
    addCentreLoad(*alone);
    drive(*alone, 2);
  }
  std::vector<double> one_s, spread_s, ratio, alone_s, ceiling;
  double alone_own_total_s = 0.0;
  const uint64_t bytes0 = comm->haloBytesSent(), ex0 = comm->haloExchanges();
  const double wait0 = comm->haloWaitSeconds();
  double spread_total_s = 0.0;
  for (int rep = 0; rep < spec.repeat; ++rep) {
    if (comm->root()) {
      const double t0 = omp_get_wtime();
      drive(*one, spec.steps);
      one_s.push_back((omp_get_wtime() - t0) / spec.steps);
    }
    comm->waitQuietly();
    comm->barrier();
    const double t0 = omp_get_wtime();
    drive(spread, spec.steps);
    comm->barrier();
    const double el = omp_get_wtime() - t0;
    spread_total_s += el;
    if (comm->root()) {
      spread_s.push_back(el / spec.steps);
      ratio.push_back(one_s.back() / spread_s.back());
    }
    if (alone) {
      comm->barrier();
      const double a0 = omp_get_wtime();
      drive(*alone, spec.steps);
      alone_own_total_s += omp_get_wtime() - a0;
      comm->barrier();
      if (comm->root()) {
        alone_s.push_back((omp_get_wtime() - a0) / spec.steps);
        ceiling.push_back(one_s.back() / alone_s.back());
      }
    }
  }
  RankScalingResult r;
  r.ranks = comm->size();
  r.elements = spec.mesh.elementCount();
  r.cuts = spread.partition().cuts;
  const double exchanges = static_cast<double>(comm->haloExchanges() - ex0);
  const double steps_run = static_cast<double>(spec.steps) * spec.repeat;
  const double mine[3] = {exchanges > 0 ? static_cast<double>(comm->haloBytesSent() - bytes0) / exchanges : 0.0,
                          (comm->haloWaitSeconds() - wait0) / spread_total_s, alone_own_total_s / steps_run};
  std::vector<double> all;
  comm->allGather(mine, 3, all);
  for (size_t q = 0; q < all.size(); q += 3) {
    r.halo_bytes_per_step.push_back(all[q]);
    r.halo_wait_fraction.push_back(all[q + 1]);
    if (alone) r.slab_alone_step_s.push_back(all[q + 2]);
  }
  if (comm->root()) {
    r.one_rank_step_s = medianOf(one_s);
    r.spread_step_s = medianOf(spread_s);
    r.speedup = medianOf(ratio);
    r.min_speedup = *std::min_element(ratio.begin(), ratio.end());
    r.max_speedup = *std::max_element(ratio.begin(), ratio.end());
    r.one_rank_seconds_per_element_step = r.one_rank_step_s / static_cast<double>(r.elements);
    if (alone) {
      r.alone_step_s = medianOf(alone_s);
      r.ceiling_speedup = medianOf(ceiling);
    }
  }
  return r;
}

namespace {

// kChains independent chains acc = acc * a + b of one native vector each: enough to fill the FMA pipes
// (2 pipes x 4 cycles latency on current cores). Returns the lane sum, so that nothing is optimised away.
template <class Real, size_t kBytes, int kChains>
RAILVIB_FORCE_INLINE double fmaChains(long iterations) {
  typedef Real Vec __attribute__((vector_size(kBytes)));
  Vec acc[kChains];
  for (int c = 0; c < kChains; ++c) acc[c] = Vec{} + static_cast<Real>(1e-3 * c);
  const Vec a = Vec{} + static_cast<Real>(0.999999), b = Vec{} + static_cast<Real>(1e-7);
  for (long it = 0; it < iterations; ++it) {
#pragma GCC unroll 16
    for (int c = 0; c < kChains; ++c) acc[c] = acc[c] * a + b;
  }
  double sum = 0.0;
  for (int c = 0; c < kChains; ++c) {
    for (size_t l = 0; l < kBytes / sizeof(Real); ++l) sum += static_cast<double>(acc[c][l]);
  }
  return sum;
}

__attribute__((target("avx512f"))) double fmaAvx512(bool dbl, long it) {
  return dbl ? fmaChains<double, 64, 16>(it) : fmaChains<float, 64, 16>(it);
}
__attribute__((target("avx2,fma"))) double fmaAvx2(bool dbl, long it) {
  return dbl ? fmaChains<double, 32, 12>(it) : fmaChains<float, 32, 12>(it);
}
double fmaSse2(bool dbl, long it) { return dbl ? fmaChains<double, 16, 12>(it) : fmaChains<float, 16, 12>(it); }

}  // namespace

FmaPeak measureFmaPeak(Precision precision, int threads, int repeat) {
  const bool dbl = precision == Precision::Double;
  const size_t real = dbl ? sizeof(double) : sizeof(float);
  __builtin_cpu_init();
  double (*loop)(bool, long) = fmaSse2;
  FmaPeak peak;
  size_t bytes = 16;
  int chains = 12;
  peak.instruction_set = "sse2 (mul + add)";
  if (__builtin_cpu_supports("avx512f")) {
    loop = fmaAvx512;
    bytes = 64;
    chains = 16;
    peak.instruction_set = "avx512f";
  } else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    loop = fmaAvx2;
    bytes = 32;
    peak.instruction_set = "avx2+fma";
  }
  const double flops_per_it = 2.0 * chains * static_cast<double>(bytes / real);
  volatile double sink = 0.0;
  // About 0.1 s per run at the calibrated rate.
  long iterations = 1000000;
  {
    const double t0 = omp_get_wtime();
    sink = sink + loop(dbl, iterations);
    const double el = omp_get_wtime() - t0;
    iterations = std::max(1000000L, static_cast<long>(0.1 * iterations / std::max(el, 1e-6)));
  }
  std::vector<double> rates;
  for (int rep = 0; rep < repeat; ++rep) {
    double el = 0.0;
    int team = 1;
#pragma omp parallel num_threads(threads)
    {
#pragma omp barrier
      const double t0 = omp_get_wtime();
      const double v = loop(dbl, iterations);
#pragma omp barrier
#pragma omp master
      {
        el = omp_get_wtime() - t0;
        team = omp_get_num_threads();
      }
#pragma omp critical
      sink = sink + v;
    }
    rates.push_back(flops_per_it * static_cast<double>(iterations) * team / el * 1e-9);
  }
  peak.threads = threads;
  peak.gflop_s = medianOf(rates);
  peak.per_core_gflop_s = peak.gflop_s / threads;
  return peak;
}

}  // namespace railvib::soil
