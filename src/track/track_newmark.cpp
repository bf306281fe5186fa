#include "railvib/track/track_newmark.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace railvib::track {

struct TrackNewmark::Solver {
  TrackSolverKind kind;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> eigen_llt;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholmod;
  // Plain CSC copy of the Eigen factor for tight, allocation-free triangular
  // solves: column j holds L_jj first (stored as 1/L_jj), then rows i > j.
  std::vector<int> col_ptr, row_idx, perm;
  std::vector<double> val;
  mutable Eigen::VectorXd work;

  explicit Solver(TrackSolverKind k) : kind(k) {}
  bool factorize(const Eigen::SparseMatrix<double>& A) {
    if (kind == TrackSolverKind::EigenSimplicialLLT) {
      eigen_llt.compute(A);
      if (eigen_llt.info() != Eigen::Success) return false;
      const Eigen::SparseMatrix<double> L = eigen_llt.matrixL();
      const int n = static_cast<int>(L.rows());
      col_ptr.assign(n + 1, 0);
      row_idx.clear();
      val.clear();
      for (int j = 0; j < n; ++j) {
        double diag = 0.0;
        std::vector<std::pair<int, double>> below;
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, j); it; ++it) {
          if (it.row() == j) {
            diag = it.value();
          } else if (it.row() > j) {
            below.emplace_back(static_cast<int>(it.row()), it.value());
          }
        }
        if (!(diag > 0.0)) return false;
        row_idx.push_back(j);
        val.push_back(1.0 / diag);
        for (const auto& [i, v] : below) {
          row_idx.push_back(i);
          val.push_back(v);
        }
        col_ptr[j + 1] = static_cast<int>(row_idx.size());
      }
      perm.resize(n);
      const auto& P = eigen_llt.permutationP().indices();
      for (int i = 0; i < n; ++i) perm[i] = P.size() ? P[i] : i;
      work.resize(n);
      return true;
    }
    cholmod.compute(A);
    return cholmod.info() == Eigen::Success;
  }
  void solveInPlace(Eigen::VectorXd& x) const {
    if (kind != TrackSolverKind::EigenSimplicialLLT) {
      x = cholmod.solve(x).eval();
      return;
    }
    // A = P^T L L^T P: y = P x; L z = y; L^T w = z; x = P^T w.
    const int n = static_cast<int>(x.size());
    double* y = work.data();
    const int* cp = col_ptr.data();
    const int* ri = row_idx.data();
    const double* lv = val.data();
    for (int i = 0; i < n; ++i) y[perm[i]] = x[i];
    for (int j = 0; j < n; ++j) {
      const double yj = (y[j] *= lv[cp[j]]);
      if (yj != 0.0) {
        for (int p = cp[j] + 1; p < cp[j + 1]; ++p) y[ri[p]] -= lv[p] * yj;
      }
    }
    for (int j = n - 1; j >= 0; --j) {
      double s = y[j];
      for (int p = cp[j] + 1; p < cp[j + 1]; ++p) s -= lv[p] * y[ri[p]];
      y[j] = s * lv[cp[j]];
    }
    for (int i = 0; i < n; ++i) x[i] = y[perm[i]];
  }
};

TrackNewmark::TrackNewmark(const TrackModel& model, double dt_s, TrackSolverKind solver)
    : model_(model), dt_(dt_s), solver_(std::make_unique<Solver>(solver)) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) throw std::invalid_argument("TrackNewmark: time step must be > 0");
  a0_ = 4.0 / (dt_ * dt_);
  a1_ = 2.0 / dt_;
  Eigen::SparseMatrix<double> keff = model_.stiffness() + a0_ * model_.mass() + a1_ * model_.damping();
  keff.makeCompressed();
  if (!solver_->factorize(keff)) {
    std::ostringstream s;
    s << "TrackNewmark: K_eff = K + 4/dt^2 M + 2/dt C is not positive definite (dt = " << dt_s
      << " s); check negative dampers (CLM d_c)";
    throw std::runtime_error(s.str());
  }
  const Eigen::Index n = model_.dofCount();
  u_ = Eigen::VectorXd::Zero(n);
  v_ = Eigen::VectorXd::Zero(n);
  a_ = Eigen::VectorXd::Zero(n);
  u_free_ = Eigen::VectorXd::Zero(n);
  rhs_.resize(n);
  tmp_.resize(n);
  tmp2_.resize(n);
}

TrackNewmark::~TrackNewmark() = default;

void TrackNewmark::solveInPlace(Eigen::VectorXd& x) const { solver_->solveInPlace(x); }

void TrackNewmark::setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t_s) {
  const Eigen::Index n = model_.dofCount();
  if (u.size() != n || v.size() != n || a.size() != n) throw std::invalid_argument("TrackNewmark: state size");
  u_ = u;
  v_ = v;
  a_ = a;
  t_ = t_s;
  steps_ = 0;
  predicted_ = false;
}

void TrackNewmark::setStaticEquilibrium(const std::vector<PointLoad>& loads, double t_s) {
  const Eigen::Index n = model_.dofCount();
  setState(model_.staticDeflection(loads), Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), t_s);
}

namespace {
/// d/dx and d2/dx2 of samples u at increasing positions xs (central differences, one-sided at the ends).
void derivatives(const std::vector<double>& xs, const std::vector<double>& u, std::vector<double>& d1,
                 std::vector<double>& d2) {
  const size_t n = xs.size();
  d1.assign(n, 0.0);
  d2.assign(n, 0.0);
  if (n < 3) return;
  for (size_t i = 0; i < n; ++i) {
    const size_t a = i == 0 ? 0 : i - 1, b = i + 1 == n ? n - 1 : i + 1;
    d1[i] = (u[b] - u[a]) / (xs[b] - xs[a]);
    const size_t c = std::min(std::max<size_t>(i, 1), n - 2);
    const double h1 = xs[c] - xs[c - 1], h2 = xs[c + 1] - xs[c];
    d2[i] = 2.0 * ((u[c + 1] - u[c]) / h2 - (u[c] - u[c - 1]) / h1) / (h1 + h2);
  }
}
}  // namespace

void TrackNewmark::setConvectedStaticState(const std::vector<PointLoad>& loads, double V, double t_s) {
  if (V == 0.0) {
    setStaticEquilibrium(loads, t_s);
    return;
  }
  const TrackModel& m = model_;
  const Eigen::VectorXd u = m.staticDeflection(loads);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(u.size()), a = Eigen::VectorXd::Zero(u.size());
  // Steady moving load: u(x, t) = U(x - V t) => v = -V U', a = V^2 U''.
  std::vector<double> d1, d2, vals;
  const std::vector<double>& xn = m.railNodePositions();
  const Rail rails[2] = {Rail::Left, Rail::Right};
  vals.resize(xn.size());
  for (int r = 0; r < m.railCount(); ++r) {
    for (int j = 0; j < m.railNodeCount(); ++j) vals[j] = u[m.railTheta(j, rails[r])];
    derivatives(xn, vals, d1, d2);
    for (int j = 0; j < m.railNodeCount(); ++j) {
      v[m.railW(j, rails[r])] = -V * u[m.railTheta(j, rails[r])];  // w' = theta exactly (Hermite)
      a[m.railW(j, rails[r])] = V * V * d1[j];
      v[m.railTheta(j, rails[r])] = -V * d1[j];
      a[m.railTheta(j, rails[r])] = V * V * d2[j];
    }
  }
  // sleeper heave, the base (and any resilient layer's node) under each rail seat and (full width)
  // the sleeper roll
  const std::vector<double>& xs = m.sleeperPositions();
  std::vector<std::function<Eigen::Index(int)>> families{[&](int s) { return m.sleeperDof(s); }};
  for (int r = 0; r < m.railCount(); ++r) families.push_back([&, r](int s) { return m.baseDof(s, rails[r]); });
  for (int r = 0; r < m.railCount(); ++r) {
    families.push_back([&, r](int s) { return m.padDof(s, rails[r]); });
    families.push_back([&, r](int s) { return m.matDof(s, rails[r]); });
  }
  if (m.railCount() == 2) families.push_back([&](int s) { return m.sleeperRollDof(s); });
  for (const auto& dof : families) {
    vals.assign(xs.size(), 0.0);
    bool present = true;
    for (int s = 0; s < m.sleeperCount(); ++s) {
      const Eigen::Index d = dof(s);
      if (d < 0) present = false;
      vals[s] = d >= 0 ? u[d] : 0.0;
    }
    if (!present) continue;
    derivatives(xs, vals, d1, d2);
    for (int s = 0; s < m.sleeperCount(); ++s) {
      const Eigen::Index d = dof(s);
      v[d] = -V * d1[s];
      a[d] = V * V * d2[s];
    }
  }
  setState(u, v, a, t_s);
}

void TrackNewmark::predict() {
  // rhs = M (a0 u + 4/dt v + a) + C (a1 u + v)
  tmp_.noalias() = a0_ * u_ + (4.0 / dt_) * v_ + a_;
  tmp2_.noalias() = a1_ * u_ + v_;
  u_free_.noalias() = model_.mass() * tmp_;
  u_free_.noalias() += model_.damping() * tmp2_;
  solveInPlace(u_free_);
  predicted_ = true;
  points_.clear();
}

void TrackNewmark::predict(const Eigen::VectorXd& other_external_force_next) {
  if (other_external_force_next.size() != model_.dofCount()) {
    throw std::invalid_argument("TrackNewmark::predict: force vector size");
  }
  tmp_.noalias() = a0_ * u_ + (4.0 / dt_) * v_ + a_;
  tmp2_.noalias() = a1_ * u_ + v_;
  u_free_ = other_external_force_next;
  u_free_.noalias() += model_.mass() * tmp_;
  u_free_.noalias() += model_.damping() * tmp2_;
  solveInPlace(u_free_);
  predicted_ = true;
  points_.clear();
}

const Eigen::VectorXd& TrackNewmark::inverseColumn(Eigen::Index d) const {
  const Eigen::Index n = model_.dofCount();
  if (columns_.empty()) columns_.resize(static_cast<size_t>(n));
  Eigen::VectorXd& col = columns_[static_cast<size_t>(d)];
  if (col.size() == 0) {
    // Bound the cache (~256 MB); columns are recomputed on demand after a reset.
    if ((cached_columns_ + 1) * static_cast<size_t>(n) * sizeof(double) > (size_t{256} << 20)) {
      for (auto& c : columns_) c.resize(0);
      cached_columns_ = 0;
    }
    col.setZero(n);
    col[d] = 1.0;
    solveInPlace(col);
    ++cached_columns_;
  }
  return col;
}

void TrackNewmark::solveUnitLoad(const RailPoint& p, Eigen::VectorXd& out) const {
  out.setZero(model_.dofCount());
  for (int k = 0; k < 4; ++k) out.noalias() += p.weights[k] * inverseColumn(p.dofs[k]);
}

double TrackNewmark::compliance(const RailPoint& a, const RailPoint& b) const {
  // r_a^T K_eff^{-1} r_b from the cached columns of b's DOFs.
  double g = 0.0;
  for (int l = 0; l < 4; ++l) g += b.weights[l] * a.displacement(inverseColumn(b.dofs[l]));
  return g;
}

void TrackNewmark::setContactPoints(const std::vector<RailPoint>& points) {
  if (!predicted_) throw std::logic_error("TrackNewmark::setContactPoints before predict()");
  points_ = points;
  const auto n = static_cast<Eigen::Index>(points.size());
  G_.resize(n, n);
  w_free_.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    w_free_[i] = points_[i].displacement(u_free_);
    for (Eigen::Index j = 0; j < n; ++j) G_(i, j) = compliance(points_[i], points_[j]);
  }
}

void TrackNewmark::commitContact(const std::vector<double>& forces_n) {
  if (!predicted_) throw std::logic_error("TrackNewmark::commitContact before predict()");
  if (forces_n.size() != points_.size()) throw std::invalid_argument("TrackNewmark::commitContact: force count");
  tmp_ = u_free_;
  for (size_t j = 0; j < forces_n.size(); ++j) {
    if (forces_n[j] == 0.0) continue;
    for (int k = 0; k < 4; ++k)
      tmp_.noalias() += (forces_n[j] * points_[j].weights[k]) * inverseColumn(points_[j].dofs[k]);
  }
  finish(tmp_);
}

void TrackNewmark::commit(const std::vector<PointLoad>& contact_loads) {
  if (!predicted_) throw std::logic_error("TrackNewmark::commit before predict()");
  bool any = false;
  rhs_.setZero();
  for (const auto& l : contact_loads) {
    if (l.force_n == 0.0) continue;
    model_.railPoint(l.x_m, l.rail).addLoad(l.force_n, rhs_);
    any = true;
  }
  if (any) {
    solveInPlace(rhs_);
    rhs_ += u_free_;
    finish(rhs_);
  } else {
    tmp_ = u_free_;
    finish(tmp_);
  }
}

void TrackNewmark::step(const std::vector<PointLoad>& loads) {
  // One back-substitution: the loads go into the right-hand side directly.
  rhs_.setZero();
  for (const auto& l : loads) {
    if (l.force_n != 0.0) model_.railPoint(l.x_m, l.rail).addLoad(l.force_n, rhs_);
  }
  tmp_.noalias() = a0_ * u_ + (4.0 / dt_) * v_ + a_;
  tmp2_.noalias() = a1_ * u_ + v_;
  rhs_.noalias() += model_.mass() * tmp_;
  rhs_.noalias() += model_.damping() * tmp2_;
  solveInPlace(rhs_);
  predicted_ = true;
  finish(rhs_);
}

void TrackNewmark::finish(const Eigen::VectorXd& u_next) {
  // a_{n+1} = 4/dt^2 (u_{n+1} - u_n) - 4/dt v_n - a_n ; v_{n+1} = v_n + dt/2 (a_n + a_{n+1})
  tmp2_.noalias() = a0_ * (u_next - u_) - (4.0 / dt_) * v_ - a_;
  v_ += (0.5 * dt_) * (a_ + tmp2_);
  a_.swap(tmp2_);
  u_ = u_next;
  t_ += dt_;
  ++steps_;
  predicted_ = false;
  points_.clear();
}

double TrackNewmark::railDisplacement(double x_m) const { return model_.railPoint(x_m).displacement(u_); }

void TrackNewmark::ballastForces(std::vector<double>& out) const { model_.ballastForceOnFoundation(u_, v_, out); }

void TrackNewmark::ballastForcesPerSeat(std::vector<double>& out) const {
  if (model_.railCount() == 1) {
    ballastForces(out);
    return;
  }
  const size_t sleepers = static_cast<size_t>(model_.sleeperCount());
  out.resize(2 * sleepers);
  for (Rail rail : {Rail::Left, Rail::Right}) {
    model_.ballastForceOnFoundation(u_, v_, seat_scratch_, rail);
    std::copy(seat_scratch_.begin(), seat_scratch_.end(),
              out.begin() + static_cast<long>(static_cast<size_t>(rail) * sleepers));
  }
}

}  // namespace railvib::track
