#include "railvib/track/track_analysis.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "railvib/track/dynamic_stiffness_lu.hpp"
#include "railvib/track/track_newmark.hpp"

namespace railvib::track {

std::vector<ReceptancePeak> findPeaks(const std::vector<double>& f, const std::vector<std::complex<double>>& r) {
  std::vector<ReceptancePeak> peaks;
  if (f.size() != r.size()) throw std::invalid_argument("findPeaks: size mismatch");
  for (size_t i = 1; i + 1 < f.size(); ++i) {
    const double a = std::abs(r[i - 1]), b = std::abs(r[i]), c = std::abs(r[i + 1]);
    if (!(b > a && b >= c)) continue;
    // parabola through (f, log|r|) at the three points
    const double x0 = f[i - 1], x1 = f[i], x2 = f[i + 1];
    const double y0 = std::log(a), y1 = std::log(b), y2 = std::log(c);
    const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
    const double curv = (d12 - d01) / (x2 - x0);
    ReceptancePeak p{x1, b};
    if (curv < 0.0) {
      // y = y1 + d (x - x1) + curv (x - x1)(x - x2)... use vertex of the interpolating parabola
      const double slope_at_x1 = d01 + curv * (x1 - x0);
      const double xv = x1 - slope_at_x1 / (2.0 * curv);
      if (xv > x0 && xv < x2) {
        p.frequency_hz = xv;
        p.magnitude_m_n = std::exp(y1 + slope_at_x1 * (xv - x1) + curv * (xv - x1) * (xv - x1));
      }
    }
    peaks.push_back(p);
  }
  return peaks;
}

double pinnedPinnedFrequency(const TrackParams& p) {
  const double L = p.layout.spacing_m;
  return (M_PI / L) * (M_PI / L) * std::sqrt(p.rail_bending_stiffness_n_m2 / p.rail_mass_per_length_kg_m) /
         (2.0 * M_PI);
}

SmearedSupport smearedSupport(const TrackParams& p, double frequency_hz) {
  using C = std::complex<double>;
  if (p.foundation == FoundationModel::Clm) {
    throw std::invalid_argument(
        "track: the smeared support has a closed form on a rigid base or the Winkler foundation, not the CLM");
  }
  const double w = 2.0 * M_PI * frequency_hz, L = p.layout.spacing_m;
  const C sp = C(p.railpad_stiffness_n_m, w * p.railpad_damping_n_s_m) / L;
  // the layers under the sleeper in series (massless junctions): compliances add
  C flex = L / C(p.ballast_stiffness_n_m, w * p.ballast_damping_n_s_m);
  for (const auto* layer : {&p.under_sleeper_pad, &p.under_ballast_mat}) {
    if (*layer) flex += L / C((*layer)->stiffnessNPerM(), w * (*layer)->dampingNsPerM());
  }
  if (p.foundation == FoundationModel::Winkler) flex += L / C(p.winkler.stiffness_n_m, w * p.winkler.damping_n_s_m);
  SmearedSupport out;
  out.below_sleeper_n_m2 = 1.0 / flex;
  const C sb = out.below_sleeper_n_m2;
  const double ms = p.sleeper_mass_kg / L;
  out.rail_support_n_m2 = sp * (sb - ms * w * w) / (sp + sb - ms * w * w);
  out.ground_force_n_m2 = sp * sb / (sp + sb - ms * w * w);
  return out;
}

std::complex<double> continuousBeamReceptance(const TrackParams& p, double frequency_hz) {
  using C = std::complex<double>;
  const double w = 2.0 * M_PI * frequency_hz;
  const C stot = smearedSupport(p, frequency_hz).rail_support_n_m2;
  const double EI = p.rail_bending_stiffness_n_m2;
  const C k4 = (p.rail_mass_per_length_kg_m * w * w - stot) / EI;
  // Of the four roots take the one with Re k > 0, Im k <= 0: waves e^{i(wt - kx)}
  // that travel away from the load and decay (x > 0).
  const C k0 = std::pow(k4, 0.25);
  C k = k0;
  C rot(1.0, 0.0);
  for (int n = 0; n < 4; ++n, rot *= C(0.0, 1.0)) {
    const C c = k0 * rot;
    if (c.real() > 0.0 && c.imag() <= 0.0) k = c;
  }
  return -C(1.0, 1.0) / (4.0 * EI * k * k * k);
}

std::complex<double> continuousBeamForceTransmissibility(const TrackParams& p, double frequency_hz) {
  const double w = 2.0 * M_PI * frequency_hz;
  const SmearedSupport s = smearedSupport(p, frequency_hz);
  return s.ground_force_n_m2 / (s.rail_support_n_m2 - p.rail_mass_per_length_kg_m * w * w);
}

std::vector<std::complex<double>> foundationForceTransmissibility(const TrackModel& model, double x_m,
                                                                  const std::vector<double>& frequencies_hz,
                                                                  RailLoading loading) {
  using Cplx = std::complex<double>;
  if (loading == RailLoading::AntiPhase) {
    throw std::invalid_argument("track: no net load in anti-phase: the force transmissibility needs one rail or both");
  }
  if (model.railCount() == 1 && loading == RailLoading::Right) {
    throw std::invalid_argument("track: a half track (track.width: half) has one rail: load it alone (left or both)");
  }
  const bool both = model.railCount() == 2 && loading == RailLoading::Both;
  Eigen::VectorXcd load = Eigen::VectorXcd::Zero(model.dofCount());
  auto addUnit = [&](Rail rail) {
    const RailPoint rp = model.railPoint(x_m, rail);
    for (int k = 0; k < 4; ++k) load[rp.dofs[k]] += rp.weights[k];
  };
  if (loading == RailLoading::Right) {
    addUnit(Rail::Right);
  } else {
    addUnit(Rail::Left);
    if (both) addUnit(Rail::Right);
  }
  const double applied_n = both ? 2.0 : 1.0;
  std::vector<Rail> seats{Rail::Left};
  if (model.railCount() == 2) seats.push_back(Rail::Right);
  DynamicStiffnessLu lu;
  std::vector<Cplx> out;
  out.reserve(frequencies_hz.size());
  std::vector<double> re, im;
  for (double f : frequencies_hz) {
    lu.factorize(model.dynamicStiffness(f), "track: transmissibility");
    const Eigen::VectorXcd u = lu.solve(load);
    const Eigen::VectorXcd v = Cplx(0.0, 2.0 * M_PI * f) * u;
    // the force is linear in (u, v): its real and imaginary parts from those of the state
    Cplx total = 0.0;
    for (Rail rail : seats) {
      model.ballastForceOnFoundation(u.real(), v.real(), re, rail);
      model.ballastForceOnFoundation(u.imag(), v.imag(), im, rail);
      for (size_t i = 0; i < re.size(); ++i) total += Cplx(re[i], im[i]);
    }
    out.push_back(total / applied_n);
  }
  return out;
}

double insertionLossDb(std::complex<double> without, std::complex<double> with) {
  return 20.0 * std::log10(std::abs(without) / std::abs(with));
}

std::vector<double> zeroCrossings(const std::vector<double>& f, const std::vector<double>& y) {
  if (f.size() != y.size()) throw std::invalid_argument("zeroCrossings: size mismatch");
  std::vector<double> out;
  for (size_t i = 0; i + 1 < f.size(); ++i) {
    if (y[i] == 0.0) {
      out.push_back(f[i]);
    } else if ((y[i] < 0.0) != (y[i + 1] < 0.0) && y[i + 1] != 0.0) {
      out.push_back(f[i] + (f[i + 1] - f[i]) * y[i] / (y[i] - y[i + 1]));
    }
  }
  if (!y.empty() && y.back() == 0.0) out.push_back(f.back());
  return out;
}

double winklerBeamStaticDeflection(double EI, double k, double force_n) {
  const double b = std::pow(k / (4.0 * EI), 0.25);
  return force_n / (8.0 * EI * b * b * b);
}

double smearedStaticSupportStiffness(const TrackParams& p) {
  double flex = 1.0 / p.railpad_stiffness_n_m + 1.0 / p.ballast_stiffness_n_m;
  for (const auto* layer : {&p.under_sleeper_pad, &p.under_ballast_mat}) {
    if (*layer) flex += 1.0 / (*layer)->stiffnessNPerM();
  }
  if (p.foundation == FoundationModel::Winkler) flex += 1.0 / p.winkler.stiffness_n_m;
  return 1.0 / flex / p.layout.spacing_m;
}

std::vector<std::complex<double>> receptanceOnGround(const TrackModel& model, double x_m,
                                                     const std::vector<double>& frequencies_hz,
                                                     const GroundCompliance& ground) {
  using Cplx = std::complex<double>;
  const TrackParams& p = model.params();
  if (p.foundation != FoundationModel::Rigid || model.railCount() != 1) {
    throw std::invalid_argument(
        "track: a ground given in the frequency domain replaces the foundation of a half track built with the rigid "
        "foundation (track.foundation.model: rigid, track.width: half)");
  }
  if (!ground) throw std::invalid_argument("track: no ground compliance given");
  const Eigen::Index n = model.sleeperCount();
  const RailPoint at = model.railPoint(x_m);
  Eigen::VectorXcd load = Eigen::VectorXcd::Zero(model.dofCount());
  for (int k = 0; k < 4; ++k) load[at.dofs[k]] += at.weights[k];
  DynamicStiffnessLu lu;
  std::vector<Cplx> out;
  out.reserve(frequencies_hz.size());
  std::vector<Eigen::Triplet<Cplx>> t;
  for (double f : frequencies_hz) {
    const double w = 2.0 * M_PI * f;
    const Eigen::MatrixXcd g = ground(f);
    if (g.rows() != n || g.cols() != n || !g.allFinite()) {
      std::ostringstream s;
      s << "track: the ground compliance at " << f << " Hz is " << g.rows() << " x " << g.cols()
        << (g.allFinite() ? "" : " with non-finite entries") << ", the track has " << n << " sleepers";
      throw std::invalid_argument(s.str());
    }
    // the layer that stands on the ground: the ballast, or an under-ballast mat
    const Cplx kb = p.under_ballast_mat
                        ? Cplx(p.under_ballast_mat->stiffnessNPerM(), w * p.under_ballast_mat->dampingNsPerM())
                        : Cplx(p.ballast_stiffness_n_m, w * p.ballast_damping_n_s_m);
    // Ballast (or mat) on the ground: f_b = k_b* (I + k_b* G)^-1 u_s, u_s the displacements of its top.
    const Eigen::MatrixXcd ballast =
        kb * (Eigen::MatrixXcd::Identity(n, n) + kb * g).partialPivLu().solve(Eigen::MatrixXcd::Identity(n, n));
    // Every entry of the sleeper block, zeros too, so that the pattern analysed once holds at every frequency.
    t.clear();
    t.reserve(static_cast<size_t>(n * (n + 1)));
    // the top of the layer on the ground: the mat node, the pad node (the ballast's top) or the sleeper
    const auto top = [&](Eigen::Index i) {
      const int s = static_cast<int>(i);
      return p.under_ballast_mat ? model.matDof(s) : p.under_sleeper_pad ? model.padDof(s) : model.sleeperDof(s);
    };
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Index si = top(i);
      t.emplace_back(si, si, -kb);  // the rigid model's ballast (or mat) to the fixed base
      for (Eigen::Index j = 0; j < n; ++j) t.emplace_back(si, top(j), ballast(i, j));
    }
    Eigen::SparseMatrix<Cplx> block(model.dofCount(), model.dofCount());
    block.setFromTriplets(t.begin(), t.end());
    Eigen::SparseMatrix<Cplx> a = model.dynamicStiffness(f) + block;
    a.makeCompressed();
    lu.factorize(a, "track: receptance on the ground");
    const Eigen::VectorXcd u = lu.solve(load);
    Cplx r = 0.0;
    for (int k = 0; k < 4; ++k) r += at.weights[k] * u[at.dofs[k]];
    out.push_back(r);
  }
  return out;
}

void simulateMovingLoads(const TrackModel& model, const MovingLoadRun& run,
                         const std::function<void(double, const std::vector<double>&)>& sink) {
  if (run.forces_n.size() != run.offsets_behind_m.size()) {
    throw std::invalid_argument("simulateMovingLoads: one offset per force");
  }
  TrackNewmark nm(model, run.dt_s);
  std::vector<PointLoad> loads(run.forces_n.size());
  auto place = [&](double t) {
    const double front = run.front_start_m + run.speed_m_s * t;
    for (size_t k = 0; k < loads.size(); ++k) {
      loads[k] = PointLoad{front - run.offsets_behind_m[k], run.forces_n[k]};
      if (loads[k].x_m < model.railStart() || loads[k].x_m > model.railEnd()) {
        std::ostringstream s;
        s << "moving load " << k << " left the rail at t = " << t << " s (x = " << loads[k].x_m << " m, rail ["
          << model.railStart() << ", " << model.railEnd() << "] m): lengthen track.extent or shorten the run";
        throw std::out_of_range(s.str());
      }
    }
  };
  place(0.0);
  nm.setStaticEquilibrium(loads, 0.0);
  std::vector<double> ballast;
  nm.ballastForces(ballast);
  sink(0.0, ballast);
  const long steps = static_cast<long>(std::llround(run.duration_s / run.dt_s));
  for (long n = 1; n <= steps; ++n) {
    const double t = static_cast<double>(n) * run.dt_s;
    place(t);
    nm.step(loads);
    nm.ballastForces(ballast);
    sink(t, ballast);
  }
}

}  // namespace railvib::track
