#include "railvib/track/track_model.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "railvib/track/dynamic_stiffness_lu.hpp"

namespace railvib::track {

namespace {
using Triplets = std::vector<Eigen::Triplet<double>>;

void addPair(Triplets& t, Eigen::Index a, Eigen::Index b, double value) {
  // Two-node spring/dashpot between DOFs a and b (b < 0: to ground).
  t.emplace_back(a, a, value);
  if (b >= 0) {
    t.emplace_back(b, b, value);
    t.emplace_back(a, b, -value);
    t.emplace_back(b, a, -value);
  }
}
}  // namespace

TrackModel::TrackModel(const TrackParams& params) : params_(params), rails_(params.width == TrackWidth::Full ? 2 : 1) {
  build();
}

size_t TrackModel::seatIndex(Rail rail) const {
  const size_t seat = rail == Rail::Left ? 0 : 1;
  if (seat >= static_cast<size_t>(rails_)) {
    throw std::invalid_argument("track: the right rail is not modelled (track.width: half models the left rail)");
  }
  return seat;
}

std::vector<double> soilRailSeatPositions(const TrackParams& params) {
  if (params.width == TrackWidth::Half) return {};
  return {params.rail_seat_offset_m, -params.rail_seat_offset_m};
}

void soilLoadFrames(const std::vector<double>& ballast, size_t sleepers, size_t seats, std::vector<double>& out) {
  if (sleepers == 0 || (seats != 1 && seats != 2) || ballast.size() % (sleepers * seats) != 0) {
    throw std::invalid_argument("soilLoadFrames: " + std::to_string(ballast.size()) + " ballast forces for " +
                                std::to_string(sleepers) + " sleepers x " + std::to_string(seats) + " rail seats");
  }
  out.resize(ballast.size());
  if (seats == 1) {
    for (size_t k = 0; k < ballast.size(); ++k) out[k] = kHalfTrackRailsOnSoil * ballast[k];
    return;
  }
  const size_t samples = ballast.size() / (sleepers * seats);
  for (size_t k = 0; k < samples; ++k) {
    for (size_t seat = 0; seat < seats; ++seat) {
      for (size_t s = 0; s < sleepers; ++s)
        out[(k * sleepers + s) * seats + seat] = ballast[(k * seats + seat) * sleepers + s];
    }
  }
}

double TrackModel::railSeatY(Rail rail) const {
  if (rails_ == 1) {
    seatIndex(rail);  // refuses the right rail
    return 0.0;
  }
  return rail == Rail::Left ? params_.rail_seat_offset_m : -params_.rail_seat_offset_m;
}

void TrackModel::build() {
  const TrackParams& p = params_;
  const double L = p.layout.spacing_m;
  const int ne = p.elements_per_bay;
  const size_t seats = static_cast<size_t>(rails_);
  sleeper_x_ = p.layout.sleeperPositions();
  const long n_s = static_cast<long>(sleeper_x_.size());
  if (n_s < 2) throw std::invalid_argument("track: fewer than 2 sleepers in the extent");
  const long n_nodes = (n_s - 1) * ne + 1;
  element_length_ = L / ne;
  node_x_.resize(n_nodes);
  for (long j = 0; j < n_nodes; ++j) node_x_[j] = sleeper_x_[0] + static_cast<double>(j) * element_length_;
  node_x_.back() = sleeper_x_.back();

  // DOF numbering node by node (banded): w, theta of each rail [, sleeper heave, roll, and under each seat
  // its pad node, mat node and base where they exist].
  rail_dof_.assign(seats, std::vector<Eigen::Index>(n_nodes, -1));
  base_dof_.assign(seats, std::vector<Eigen::Index>(n_s, -1));
  pad_dof_.assign(seats, std::vector<Eigen::Index>(n_s, -1));
  mat_dof_.assign(seats, std::vector<Eigen::Index>(n_s, -1));
  sleeper_dof_.assign(n_s, -1);
  roll_dof_.assign(n_s, -1);
  Eigen::Index idx = 0;
  for (long j = 0; j < n_nodes; ++j) {
    for (size_t r = 0; r < seats; ++r) {
      rail_dof_[r][j] = idx;
      idx += 2;
    }
    if (j % ne == 0) {
      const long i = j / ne;
      sleeper_dof_[i] = idx++;
      if (rails_ == 2) roll_dof_[i] = idx++;
      for (size_t r = 0; r < seats; ++r) {
        // the seat chain top to bottom: pad node, mat node, base (each only where it exists)
        if (p.under_sleeper_pad) pad_dof_[r][i] = idx++;
        if (p.under_ballast_mat) mat_dof_[r][i] = idx++;
        if (p.foundation != FoundationModel::Rigid) base_dof_[r][i] = idx++;
      }
    }
  }
  n_dof_ = idx;

  // End damping layers: eta(x) = eta_max * (depth / L_abs)^2.
  const double labs = p.ends.absorbing_length_m;
  const double x0 = node_x_.front(), x1 = node_x_.back();
  auto eta = [&](double x) {
    if (labs <= 0.0 || p.ends.max_damping_rate_1_s <= 0.0) return 0.0;
    const double depth = std::max({0.0, (x0 + labs) - x, x - (x1 - labs)});
    const double r = std::min(1.0, depth / labs);
    return p.ends.max_damping_rate_1_s * r * r;
  };

  Triplets tm, tc, tk;
  const double h = element_length_;
  const double EI = p.rail_bending_stiffness_n_m2;
  const double m = p.rail_mass_per_length_kg_m;
  const double ke[4][4] = {{12, 6 * h, -12, 6 * h},
                           {6 * h, 4 * h * h, -6 * h, 2 * h * h},
                           {-12, -6 * h, 12, -6 * h},
                           {6 * h, 2 * h * h, -6 * h, 4 * h * h}};
  const double me[4][4] = {{156, 22 * h, 54, -13 * h},
                           {22 * h, 4 * h * h, 13 * h, -3 * h * h},
                           {54, 13 * h, 156, -22 * h},
                           {-13 * h, -3 * h * h, -22 * h, 4 * h * h}};
  const double kf = EI / (h * h * h);
  const double mf = m * h / 420.0;
  for (size_t r = 0; r < seats; ++r) {
    for (long e = 0; e + 1 < n_nodes; ++e) {
      const Eigen::Index d[4] = {rail_dof_[r][e], rail_dof_[r][e] + 1, rail_dof_[r][e + 1], rail_dof_[r][e + 1] + 1};
      const double eta_e = eta(0.5 * (node_x_[e] + node_x_[e + 1]));
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
          tk.emplace_back(d[a], d[b], kf * ke[a][b]);
          tm.emplace_back(d[a], d[b], mf * me[a][b]);
          if (eta_e > 0.0) tc.emplace_back(d[a], d[b], eta_e * mf * me[a][b]);
        }
      }
    }
  }
  for (long i = 0; i < n_s; ++i) {
    const Eigen::Index s = sleeper_dof_[i], roll = roll_dof_[i];
    const double eta_s = eta(sleeper_x_[i]);
    // sleeper heave: the half track's half sleeper, or the whole sleeper; roll: its inertia
    const double heave_mass = p.sleeper_mass_kg * static_cast<double>(seats);
    tm.emplace_back(s, s, heave_mass);
    if (eta_s > 0.0) tc.emplace_back(s, s, eta_s * heave_mass);
    if (roll >= 0) {
      tm.emplace_back(roll, roll, p.sleeper_roll_inertia_kg_m2);
      if (eta_s > 0.0) tc.emplace_back(roll, roll, eta_s * p.sleeper_roll_inertia_kg_m2);
    }
    for (size_t r = 0; r < seats; ++r) {
      // The seat at lateral y moves down by heave + y roll: a spring from a DOF x to the seat is
      // the pair (x, heave) plus the lever terms of the roll.
      const double y = railSeatY(r == 0 ? Rail::Left : Rail::Right);
      const Eigen::Index w = rail_dof_[r][i * ne];
      const Eigen::Index b = base_dof_[r][i];
      auto seatSpring = [&](Triplets& t, Eigen::Index other, double value) {
        // energy value (u_other - u_seat)^2 / 2, u_seat = u_s + y u_roll (other < 0: ground)
        const Eigen::Index dofs[3] = {other, s, roll};
        const double coef[3] = {1.0, -1.0, -y};
        for (int a = 0; a < 3; ++a) {
          for (int c = 0; c < 3; ++c) {
            if (dofs[a] < 0 || dofs[c] < 0 || coef[a] == 0.0 || coef[c] == 0.0) continue;
            t.emplace_back(dofs[a], dofs[c], value * coef[a] * coef[c]);
          }
        }
      };
      // railpad rail -> seat
      seatSpring(tk, w, p.railpad_stiffness_n_m);
      if (p.railpad_damping_n_s_m > 0.0) seatSpring(tc, w, p.railpad_damping_n_s_m);
      // ballast from its top (the seat, or the pad node under an under-sleeper pad) to its bottom
      // (the base or ground, or the mat node over an under-ballast mat); the layers are springs and
      // dampers in series through massless nodes
      const Eigen::Index pad = pad_dof_[r][i], mat = mat_dof_[r][i];
      const Eigen::Index ballast_bottom = p.under_ballast_mat ? mat : b;
      if (p.under_sleeper_pad) {
        const ResilientLayer& usp = *p.under_sleeper_pad;
        seatSpring(tk, pad, usp.stiffnessNPerM());
        if (usp.dampingNsPerM() > 0.0) seatSpring(tc, pad, usp.dampingNsPerM());
        addPair(tk, pad, ballast_bottom, p.ballast_stiffness_n_m);
        if (p.ballast_damping_n_s_m > 0.0) addPair(tc, pad, ballast_bottom, p.ballast_damping_n_s_m);
      } else {
        seatSpring(tk, ballast_bottom, p.ballast_stiffness_n_m);
        if (p.ballast_damping_n_s_m > 0.0) seatSpring(tc, ballast_bottom, p.ballast_damping_n_s_m);
      }
      if (p.under_ballast_mat) {
        const ResilientLayer& ubm = *p.under_ballast_mat;
        addPair(tk, mat, b, ubm.stiffnessNPerM());
        if (ubm.dampingNsPerM() > 0.0) addPair(tc, mat, b, ubm.dampingNsPerM());
      }
      if (p.foundation == FoundationModel::Clm) {
        tm.emplace_back(b, b, p.clm.mass_kg);
        if (eta_s > 0.0) tc.emplace_back(b, b, eta_s * p.clm.mass_kg);
        tk.emplace_back(b, b, p.clm.stiffness_n_m);
        tc.emplace_back(b, b, p.clm.damping_n_s_m);
        if (i + 1 < n_s) {
          addPair(tk, b, base_dof_[r][i + 1], p.clm.coupling_stiffness_n_m);
          addPair(tc, b, base_dof_[r][i + 1], p.clm.coupling_damping_n_s_m);
        }
      } else if (p.foundation == FoundationModel::Winkler) {
        // massless series node: Winkler spring and damper to ground
        tk.emplace_back(b, b, p.winkler.stiffness_n_m);
        tc.emplace_back(b, b, p.winkler.damping_n_s_m);
      }
    }
  }
  M_.resize(n_dof_, n_dof_);
  C_.resize(n_dof_, n_dof_);
  K_.resize(n_dof_, n_dof_);
  M_.setFromTriplets(tm.begin(), tm.end());
  C_.setFromTriplets(tc.begin(), tc.end());
  K_.setFromTriplets(tk.begin(), tk.end());
  M_.makeCompressed();
  C_.makeCompressed();
  K_.makeCompressed();
}

int TrackModel::nearestSleeper(double x_m) const {
  size_t best = 0;
  for (size_t i = 1; i < sleeper_x_.size(); ++i) {
    if (std::abs(sleeper_x_[i] - x_m) < std::abs(sleeper_x_[best] - x_m)) best = i;
  }
  return static_cast<int>(best);
}

RailPoint TrackModel::railPoint(double x_m, Rail rail) const {
  const double x0 = node_x_.front(), x1 = node_x_.back();
  const double tol = 1e-9 * std::max(1.0, std::abs(x1 - x0));
  if (!(x_m >= x0 - tol && x_m <= x1 + tol)) {
    std::ostringstream s;
    s << "track: position " << x_m << " m is outside the rail [" << x0 << ", " << x1 << "] m";
    throw std::out_of_range(s.str());
  }
  const double h = element_length_;
  long e = static_cast<long>(std::floor((x_m - x0) / h));
  e = std::clamp(e, 0L, static_cast<long>(node_x_.size()) - 2);
  const double xi = std::clamp((x_m - node_x_[e]) / h, 0.0, 1.0);
  const double xi2 = xi * xi, xi3 = xi2 * xi;
  RailPoint p;
  p.x_m = x_m;
  const std::vector<Eigen::Index>& dof = rail_dof_[seatIndex(rail)];
  p.dofs = {dof[e], dof[e] + 1, dof[e + 1], dof[e + 1] + 1};
  p.weights = {1.0 - 3.0 * xi2 + 2.0 * xi3, h * (xi - 2.0 * xi2 + xi3), 3.0 * xi2 - 2.0 * xi3, h * (xi3 - xi2)};
  p.slope_weights = {(6.0 * xi2 - 6.0 * xi) / h, 1.0 - 4.0 * xi + 3.0 * xi2, (6.0 * xi - 6.0 * xi2) / h,
                     3.0 * xi2 - 2.0 * xi};
  return p;
}

Eigen::VectorXd TrackModel::loadVector(const std::vector<PointLoad>& loads) const {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n_dof_);
  for (const auto& l : loads) railPoint(l.x_m, l.rail).addLoad(l.force_n, f);
  return f;
}

void TrackModel::ballastForceOnFoundation(const Eigen::VectorXd& u, const Eigen::VectorXd& v, std::vector<double>& out,
                                          Rail rail) const {
  const size_t n = sleeper_x_.size();
  out.resize(n);
  const double kb = params_.ballast_stiffness_n_m, db = params_.ballast_damping_n_s_m;
  const size_t seat = seatIndex(rail);
  const std::vector<Eigen::Index>& base = base_dof_[seat];
  const double y = railSeatY(rail);
  if (params_.under_ballast_mat) {
    // the foundation stands under the mat: the mat's force (equal to the ballast's, the mat node
    // being massless, up to the time integration's round-off)
    const double km = params_.under_ballast_mat->stiffnessNPerM(), dm = params_.under_ballast_mat->dampingNsPerM();
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Index m = mat_dof_[seat][i], b = base[i];
      out[i] = km * (u[m] - (b >= 0 ? u[b] : 0.0)) + dm * (v[m] - (b >= 0 ? v[b] : 0.0));
    }
    return;
  }
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Index s = sleeper_dof_[i], roll = roll_dof_[i], b = base[i], pad = pad_dof_[seat][i];
    // the ballast's top: the seat (moving by heave + y roll), or the node under an under-sleeper pad
    const double top_u = pad >= 0 ? u[pad] : (roll >= 0 ? u[s] + y * u[roll] : u[s]);
    const double top_v = pad >= 0 ? v[pad] : (roll >= 0 ? v[s] + y * v[roll] : v[s]);
    const double du = top_u - (b >= 0 ? u[b] : 0.0);
    const double dv = top_v - (b >= 0 ? v[b] : 0.0);
    out[i] = kb * du + db * dv;
  }
}

std::vector<double> TrackModel::ballastForceOnFoundation(const Eigen::VectorXd& u, const Eigen::VectorXd& v,
                                                         Rail rail) const {
  std::vector<double> out;
  ballastForceOnFoundation(u, v, out, rail);
  return out;
}

Eigen::VectorXd TrackModel::staticDeflection(const std::vector<PointLoad>& loads) const {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(K_);
  if (ldlt.info() != Eigen::Success) throw std::runtime_error("track: stiffness matrix factorisation failed");
  return ldlt.solve(loadVector(loads));
}

std::complex<double> TrackModel::receptance(double x_m, double frequency_hz) const {
  return receptance(x_m, std::vector<double>{frequency_hz}).front();
}

std::vector<std::complex<double>> TrackModel::receptance(double x_m, const std::vector<double>& frequencies_hz) const {
  return receptance(x_m, frequencies_hz, RailLoading::Left);
}

std::vector<std::complex<double>> TrackModel::receptance(double x_m, const std::vector<double>& frequencies_hz,
                                                         RailLoading loading) const {
  using Cplx = std::complex<double>;
  if (rails_ == 1 && loading != RailLoading::Left && loading != RailLoading::Both) {
    throw std::invalid_argument("track: a half track (track.width: half) has one rail: load it alone (left or both)");
  }
  // the load vector, and the observed rail (its interpolation weights)
  Eigen::VectorXcd load = Eigen::VectorXcd::Zero(n_dof_);
  auto addUnit = [&](Rail rail, double force) {
    const RailPoint rp = railPoint(x_m, rail);
    for (int k = 0; k < 4; ++k) load[rp.dofs[k]] += force * rp.weights[k];
  };
  const bool both_rails = rails_ == 2 && (loading == RailLoading::Both || loading == RailLoading::AntiPhase);
  if (loading == RailLoading::Right) {
    addUnit(Rail::Right, 1.0);
  } else {
    addUnit(Rail::Left, 1.0);
    if (both_rails) addUnit(Rail::Right, loading == RailLoading::AntiPhase ? -1.0 : 1.0);
  }
  const RailPoint observed = railPoint(x_m, loading == RailLoading::Right ? Rail::Right : Rail::Left);
  Eigen::VectorXcd r = Eigen::VectorXcd::Zero(n_dof_);
  for (int k = 0; k < 4; ++k) r[observed.dofs[k]] += observed.weights[k];
  DynamicStiffnessLu lu;
  std::vector<Cplx> out;
  out.reserve(frequencies_hz.size());
  for (double f : frequencies_hz) {
    lu.factorize(dynamicStiffness(f), "track: receptance");
    const Eigen::VectorXcd x = lu.solve(load);
    out.push_back(r.transpose() * x);
  }
  return out;
}

Eigen::SparseMatrix<std::complex<double>> TrackModel::dynamicStiffness(double frequency_hz) const {
  using Cplx = std::complex<double>;
  const double w = 2.0 * M_PI * frequency_hz;
  Eigen::SparseMatrix<Cplx> a = K_.cast<Cplx>() - (w * w) * M_.cast<Cplx>() + Cplx(0.0, w) * C_.cast<Cplx>();
  a.makeCompressed();
  return a;
}

double TrackModel::strainEnergy(const Eigen::VectorXd& u) const { return 0.5 * u.dot(K_ * u); }
double TrackModel::kineticEnergy(const Eigen::VectorXd& v) const { return 0.5 * v.dot(M_ * v); }

bool TrackModel::dampingIsPositiveSemiDefinite() const {
  // Every damper is PSD except the CLM coupling chain d_f I + d_c Lap, whose
  // eigenvalues lie in [d_f + 4 min(d_c,0), ...]; ballast dampers only add.
  if (params_.foundation != FoundationModel::Clm) return true;
  return params_.clm.damping_n_s_m + 4.0 * std::min(0.0, params_.clm.coupling_damping_n_s_m) >= 0.0;
}

}  // namespace railvib::track
