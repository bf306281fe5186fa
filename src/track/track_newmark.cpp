#include "railvib/track/track_newmark.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace railvib::track {

struct TrackNewmark::Solver {
  TrackSolverKind kind;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> eigen_llt;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholmod;
  Eigen::VectorXd work;

  explicit Solver(TrackSolverKind k) : kind(k) {}
  bool factorize(const Eigen::SparseMatrix<double>& A) {
    if (kind == TrackSolverKind::EigenSimplicialLLT) {
      eigen_llt.compute(A);
      return eigen_llt.info() == Eigen::Success;
    }
    cholmod.compute(A);
    return cholmod.info() == Eigen::Success;
  }
  void solveInPlace(Eigen::VectorXd& x) {
    if (kind == TrackSolverKind::EigenSimplicialLLT) {
      // P^T L L^T P x = b, solved in place without allocation.
      work.resize(x.size());
      work.noalias() = eigen_llt.permutationP() * x;
      eigen_llt.matrixL().solveInPlace(work);
      eigen_llt.matrixU().solveInPlace(work);
      x.noalias() = eigen_llt.permutationPinv() * work;
    } else {
      x = cholmod.solve(x).eval();
    }
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

void TrackNewmark::setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                            double t_s) {
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

void TrackNewmark::solveUnitLoad(const RailPoint& p, Eigen::VectorXd& out) const {
  out.setZero(model_.dofCount());
  p.addLoad(1.0, out);
  solveInPlace(out);
}

double TrackNewmark::compliance(const RailPoint& a, const RailPoint& b) const {
  Eigen::VectorXd g;
  solveUnitLoad(b, g);
  return a.displacement(g);
}

void TrackNewmark::setContactPoints(const std::vector<RailPoint>& points) {
  if (!predicted_) throw std::logic_error("TrackNewmark::setContactPoints before predict()");
  points_ = points;
  const size_t n = points.size();
  if (unit_.size() < n) unit_.resize(n);
  G_.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  w_free_.resize(static_cast<Eigen::Index>(n));
  for (size_t j = 0; j < n; ++j) solveUnitLoad(points[j], unit_[j]);
  for (size_t i = 0; i < n; ++i) {
    w_free_[static_cast<Eigen::Index>(i)] = points[i].displacement(u_free_);
    for (size_t j = 0; j < n; ++j) {
      G_(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = points[i].displacement(unit_[j]);
    }
  }
}

void TrackNewmark::commitContact(const std::vector<double>& forces_n) {
  if (!predicted_) throw std::logic_error("TrackNewmark::commitContact before predict()");
  if (forces_n.size() != points_.size()) throw std::invalid_argument("TrackNewmark::commitContact: force count");
  tmp_ = u_free_;
  for (size_t j = 0; j < forces_n.size(); ++j) {
    if (forces_n[j] != 0.0) tmp_.noalias() += forces_n[j] * unit_[j];
  }
  finish(tmp_);
}

void TrackNewmark::commit(const std::vector<PointLoad>& contact_loads) {
  if (!predicted_) throw std::logic_error("TrackNewmark::commit before predict()");
  bool any = false;
  rhs_.setZero();
  for (const auto& l : contact_loads) {
    if (l.force_n == 0.0) continue;
    model_.railPoint(l.x_m).addLoad(l.force_n, rhs_);
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
    if (l.force_n != 0.0) model_.railPoint(l.x_m).addLoad(l.force_n, rhs_);
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

}  // namespace railvib::track
