#include "railvib/vehicle/passage.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/track/track_newmark.hpp"

namespace railvib::vehicle {

// ------------------------------------------------------------------ contact
int solveHertzContact(const Eigen::VectorXd& d_free, const Eigen::MatrixXd& G, double C, Eigen::VectorXd& F,
                      double tol_n) {
  const Eigen::Index n = d_free.size();
  if (F.size() != n) F = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd delta(n), R(n), dF(n), Ftrial(n);
  Eigen::MatrixXd J(n, n);
  auto residual = [&](const Eigen::VectorXd& f, Eigen::VectorXd& r, Eigen::VectorXd& d) {
    d = d_free - G * f;
    for (Eigen::Index i = 0; i < n; ++i) r[i] = f[i] - (d[i] > 0.0 ? C * d[i] * std::sqrt(d[i]) : 0.0);
    return r.lpNorm<Eigen::Infinity>();
  };
  double rnorm = residual(F, R, delta);
  for (int it = 1; it <= 100; ++it) {
    J = G;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double k = delta[i] > 0.0 ? 1.5 * C * std::sqrt(delta[i]) : 0.0;
      J.row(i) *= k;
      J(i, i) += 1.0;
    }
    dF = J.partialPivLu().solve(-R);
    // damped Newton: halve the step until the residual decreases
    double lambda = 1.0, rtrial = 0.0;
    Eigen::VectorXd dtrial(n), Rtrial(n);
    for (int h = 0; h < 40; ++h) {
      Ftrial = F + lambda * dF;
      rtrial = residual(Ftrial, Rtrial, dtrial);
      if (rtrial < rnorm || rtrial <= tol_n) break;
      lambda *= 0.5;
    }
    F = Ftrial;
    R = Rtrial;
    delta = dtrial;
    rnorm = rtrial;
    if ((lambda * dF).lpNorm<Eigen::Infinity>() <= tol_n && rnorm <= 1e3 * tol_n) return it;
  }
  std::ostringstream msg;
  msg << "Hertz contact: Newton did not converge in 100 iterations (residual " << rnorm << " N)";
  throw std::runtime_error(msg.str());
}

// ------------------------------------------------------------------ rigid rail
Eigen::MatrixXd RigidRail::staticCompliance(const std::vector<double>& x) {
  return Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(x.size()), static_cast<Eigen::Index>(x.size()));
}

void RigidRail::prepareStep(const std::vector<double>& x, Eigen::VectorXd& free, Eigen::MatrixXd& G) {
  const auto n = static_cast<Eigen::Index>(x.size());
  free.setZero(n);
  G.setZero(n, n);
}

// ------------------------------------------------------------------ flexible rail
struct FlexibleRail::Impl {
  Impl(const track::TrackParams& p, double dt) : model(p), newmark(model, dt) {}
  track::TrackModel model;
  track::TrackNewmark newmark;
  std::vector<track::RailPoint> points;
};

FlexibleRail::FlexibleRail(const track::TrackParams& params, double dt_s)
    : impl_(std::make_unique<Impl>(params, dt_s)) {}
FlexibleRail::~FlexibleRail() = default;

const track::TrackNewmark& FlexibleRail::integrator() const { return impl_->newmark; }

int FlexibleRail::railSeatCount() const { return impl_->model.railCount(); }

Eigen::MatrixXd FlexibleRail::staticCompliance(const std::vector<double>& x) {
  const auto n = static_cast<Eigen::Index>(x.size());
  Eigen::MatrixXd G(n, n);
  std::vector<track::RailPoint> pts;
  for (size_t i = 0; i < x.size(); ++i) pts.push_back(impl_->model.railPoint(x[i], wheelRail(i)));
  for (Eigen::Index j = 0; j < n; ++j) {
    const auto jj = static_cast<size_t>(j);
    const Eigen::VectorXd u = impl_->model.staticDeflection({track::PointLoad{x[jj], 1.0, wheelRail(jj)}});
    for (Eigen::Index i = 0; i < n; ++i) G(i, j) = pts[i].displacement(u);
  }
  return 0.5 * (G + G.transpose());
}

void FlexibleRail::start(const std::vector<double>& x, const std::vector<double>& F, double t_s, double V) {
  std::vector<track::PointLoad> loads;
  for (size_t i = 0; i < x.size(); ++i) loads.push_back({x[i], F[i], wheelRail(i)});
  impl_->newmark.setConvectedStaticState(loads, V, t_s);
}

void FlexibleRail::prepareStep(const std::vector<double>& x, Eigen::VectorXd& free, Eigen::MatrixXd& G) {
  auto& I = *impl_;
  I.points.resize(x.size());
  for (size_t i = 0; i < x.size(); ++i) I.points[i] = I.model.railPoint(x[i], wheelRail(i));
  I.newmark.predict();
  I.newmark.setContactPoints(I.points);
  free = I.newmark.contactFreeDisplacements();
  G = I.newmark.contactCompliance();
}

void FlexibleRail::commitStep(const std::vector<double>& F) { impl_->newmark.commitContact(F); }

void FlexibleRail::ballastForces(std::vector<double>& out) const { impl_->newmark.ballastForcesPerSeat(out); }

std::vector<double> FlexibleRail::sleeperPositions() const { return impl_->model.sleeperPositions(); }
double FlexibleRail::xMin() const { return impl_->model.interiorStart(); }
double FlexibleRail::xMax() const { return impl_->model.interiorEnd(); }

std::unique_ptr<RailSupport> makeRailSupport(const PassageParams& params, const track::TrackParams& track) {
  if (params.vehicle_track == VehicleTrack::Rigid) return std::make_unique<RigidRail>();
  return std::make_unique<FlexibleRail>(track, params.time_step_s);
}

// ------------------------------------------------------------------ statics
StaticState staticEquilibrium(const VehicleModel& model, RailSupport& rail, const std::vector<double>& x,
                              const std::vector<double>& z) {
  rail.setWheelRails(model.wheelRails());  // each wheel on its own rail
  return staticEquilibrium(model, rail.staticCompliance(x), z);
}

StaticState staticEquilibrium(const VehicleModel& model, const Eigen::MatrixXd& Gs, const std::vector<double>& z) {
  const Eigen::MatrixXd& K = model.stiffness();
  const Eigen::MatrixXd& B = model.contactSelection();
  const Eigen::VectorXd& fg = model.gravityLoad();
  const double C = model.params().hertz_constant_n_m1_5;
  const int nw = model.wheelCount();
  if (Gs.rows() != nw || Gs.cols() != nw || static_cast<int>(z.size()) != nw)
    throw std::invalid_argument("static equilibrium: one rail compliance row and unevenness per wheel");
  const Eigen::VectorXd zv = Eigen::Map<const Eigen::VectorXd>(z.data(), nw);
  const double W = model.weight();
  const double f_mean = W / nw;
  // initial guess: linearised Hertz springs at the mean wheel load
  const double d0 = std::pow(f_mean / C, 2.0 / 3.0);
  const double k0 = 1.5 * C * std::sqrt(d0);
  StaticState s;
  s.q = (K + k0 * B * B.transpose()).ldlt().solve(fg + k0 * B * (Eigen::VectorXd::Constant(nw, d0) - zv));
  s.contact_force_n = Eigen::VectorXd::Constant(nw, f_mean);
  const double tol = 1e-12 * f_mean;
  for (int it = 1; it <= 60; ++it) {
    const Eigen::VectorXd dfree = B.transpose() * s.q + zv;
    solveHertzContact(dfree, Gs, C, s.contact_force_n, tol);
    const Eigen::VectorXd R = K * s.q + B * s.contact_force_n - fg;
    s.iterations = it;
    const Eigen::VectorXd delta = dfree - Gs * s.contact_force_n;
    Eigen::VectorXd D(nw);
    for (int i = 0; i < nw; ++i) D[i] = delta[i] > 0.0 ? 1.5 * C * std::sqrt(delta[i]) : 0.0;
    // converged to round-off: the residual floor is ~1e-16 |K| |q| ~ 1e-9 N
    if (R.lpNorm<Eigen::Infinity>() <= 1e-13 * W && it > 1) break;
    // dF/dq = (I + D Gs)^{-1} D B^T
    const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(nw, nw) + D.asDiagonal() * Gs;
    const Eigen::MatrixXd dFdq = A.partialPivLu().solve(D.asDiagonal() * B.transpose());
    const Eigen::MatrixXd KT = K + B * dFdq;
    s.q -= KT.partialPivLu().solve(R);
    if (it == 60 && R.lpNorm<Eigen::Infinity>() > 1e-9 * W) {
      throw std::runtime_error("static equilibrium: Newton did not converge");
    }
  }
  s.rail_displacement_m = Gs * s.contact_force_n;
  s.compression_m = B.transpose() * s.q + zv - s.rail_displacement_m;
  return s;
}

// ------------------------------------------------------------------ passage
void PassageBlock::clear() {
  time_s.clear();
  wheel_x_m.clear();
  contact_force_n.clear();
  unevenness_m.clear();
  rail_displacement_m.clear();
  wheel_displacement_m.clear();
  poses.clear();
  ballast_force_n.clear();
}

VehiclePassage::VehiclePassage(const VehicleModel& model, const Unevenness& unevenness, const PassageParams& params,
                               std::unique_ptr<RailSupport> rail, PassageOptions options)
    : model_(model), unevenness_(unevenness), params_(params), rail_(std::move(rail)), options_(options) {
  nw_ = model_.wheelCount();
  // Each wheel on its own rail (the half vehicle: every wheel on the half track's left rail). The
  // vehicle and the flexible track have the same width (track.width, one switch); a rail support of
  // the other width is a programming error.
  if (!rail_->isRigid() && (rail_->railSeatCount() == 2) != model_.fullWidth()) {
    throw std::invalid_argument("VehiclePassage: the vehicle and the track have different widths (track.width)");
  }
  rail_->setWheelRails(model_.wheelRails());
  const double dt = params_.time_step_s;
  // ---- accuracy of the time step (Newmark beta = 1/4 is unconditionally stable), from the
  // lightest body on the contact and the smallest wheel, whatever the vehicle
  {
    const double C = model_.params().hertz_constant_n_m1_5;
    const double f_mean = model_.weight() / nw_;  // mean static wheel load, either width
    const double kH = 1.5 * C * std::sqrt(std::pow(f_mean / C, 2.0 / 3.0));
    const auto& wheels = model_.wheels();
    const auto by_mass = [](const WheelInfo& a, const WheelInfo& b) { return a.contact_mass_kg < b.contact_mass_kg; };
    const auto by_radius = [](const WheelInfo& a, const WheelInfo& b) { return a.radius_m < b.radius_m; };
    const double m_min = std::min_element(wheels.begin(), wheels.end(), by_mass)->contact_mass_kg;
    const double f_contact = std::sqrt(kH / m_min) / (2.0 * M_PI);  // wheel-on-Hertz mode (upper bound)
    const double steps_per_period = 1.0 / (f_contact * dt);
    const auto& d = unevenness_.params().defect;
    double defect_time = 1e300;
    if (d.enabled && d.height_m > 0.0) {
      const double R = std::min_element(wheels.begin(), wheels.end(), by_radius)->radius_m;
      defect_time = (2.0 * defectClimbLength(d, R) + d.length_m) / params_.speed_m_s;
    }
    std::ostringstream msg;
    if (steps_per_period < 20.0) {
      msg << "simulation.time_step_s = " << dt << " s is too coarse: the wheel-on-contact mode (~" << f_contact
          << " Hz) needs at least 20 steps per period (dt <= " << 1.0 / (20.0 * f_contact) << " s)";
      throw ConfigError(msg.str());
    }
    if (defect_time / dt < 100.0) {
      msg << "simulation.time_step_s = " << dt << " s is too coarse: the defect is crossed in " << defect_time * 1e3
          << " ms and needs at least 100 steps (dt <= " << defect_time / 100.0 << " s)";
      throw ConfigError(msg.str());
    }
  }
  // ---- wheels must stay on the usable rail
  {
    std::vector<double> x0, x1;
    positionsAt(0.0, x0);
    positionsAt(params_.duration_s, x1);
    const double lo = *std::min_element(x0.begin(), x0.end());
    const double hi = *std::max_element(x1.begin(), x1.end());
    if (lo < rail_->xMin() || hi > rail_->xMax()) {
      std::ostringstream msg;
      msg << "the wheels run over x in [" << lo << ", " << hi
          << "] m during simulation.duration_s = " << params_.duration_s << " s, outside the usable track ["
          << rail_->xMin() << ", " << rail_->xMax()
          << "] m (track.extent minus the absorbing ends): extend the track or shorten the run";
      throw ConfigError(msg.str());
    }
  }
  // ---- Newmark matrices (vehicle)
  const Eigen::MatrixXd& M = model_.mass();
  const Eigen::MatrixXd& C = model_.damping();
  const Eigen::MatrixXd& K = model_.stiffness();
  const Eigen::MatrixXd& B = model_.contactSelection();
  const double a0 = 4.0 / (dt * dt), a1 = 2.0 / dt, a2 = 4.0 / dt;
  const Eigen::MatrixXd Keff = K + a0 * M + a1 * C;
  const Eigen::MatrixXd H = Keff.inverse();
  Pq_ = H * (a0 * M + a1 * C);
  Pv_ = H * (a2 * M + C);
  Pa_ = H * M;
  hg_ = H * model_.gravityLoad();
  HB_ = H * B;
  Gv_ = B.transpose() * HB_;

  // ---- static equilibrium at t = 0
  positionsAt(0.0, x_);
  radius_.resize(nw_);
  z_.resize(nw_);
  for (int i = 0; i < nw_; ++i) {
    radius_[i] = model_.wheels()[i].radius_m;
    z_[i] = unevenness_.height(x_[i], radius_[i], model_.wheels()[i].rail);
  }
  static_ = staticEquilibrium(model_, *rail_, x_, z_);
  q_ = static_.q;
  v_ = Eigen::VectorXd::Zero(q_.size());
  a_ = Eigen::VectorXd::Zero(q_.size());
  F_.assign(static_.contact_force_n.data(), static_.contact_force_n.data() + nw_);
  w_rail_.assign(static_.rail_displacement_m.data(), static_.rail_displacement_m.data() + nw_);
  Fv_ = static_.contact_force_n;
  rail_->start(x_, F_, 0.0, params_.convected_track_start ? params_.speed_m_s : 0.0);
  tol_n_ = params_.contact_tolerance * model_.weight() / nw_;
}

void VehiclePassage::positionsAt(double t, std::vector<double>& x) const {
  x.resize(model_.wheelCount());
  const double front = frontAxlePosition(t);
  for (int i = 0; i < model_.wheelCount(); ++i) x[i] = front - model_.wheels()[i].offset_m;
}

uint64_t VehiclePassage::totalSamples() const {
  return static_cast<uint64_t>(std::llround(params_.duration_s / params_.time_step_s)) + 1;
}

void VehiclePassage::step() {
  const double dt = params_.time_step_s;
  const double t1 = static_cast<double>(step_ + 1) * dt;
  positionsAt(t1, x_);
  for (int i = 0; i < nw_; ++i) z_[i] = unevenness_.height(x_[i], radius_[i], model_.wheels()[i].rail);
  qs_.noalias() = Pq_ * q_;
  qs_.noalias() += Pv_ * v_;
  qs_.noalias() += Pa_ * a_;
  qs_ += hg_;
  rail_->prepareStep(x_, wr_free_, Gr_);
  dfree_.resize(nw_);
  for (int i = 0; i < nw_; ++i) dfree_[i] = qs_[model_.wheels()[i].contact_dof] - wr_free_[i] + z_[i];
  G_ = Gv_ + Gr_;
  const int it = solveHertzContact(dfree_, G_, model_.params().hertz_constant_n_m1_5, Fv_, tol_n_);
  max_iter_ = std::max(max_iter_, it);
  for (int i = 0; i < nw_; ++i) F_[i] = Fv_[i];
  rail_->commitStep(F_);
  const Eigen::VectorXd wr = wr_free_ + Gr_ * Fv_;
  for (int i = 0; i < nw_; ++i) w_rail_[i] = wr[i];
  qs_.noalias() -= HB_ * Fv_;
  // Newmark update (beta = 1/4, gamma = 1/2)
  const Eigen::VectorXd a_new = (4.0 / (dt * dt)) * (qs_ - q_) - (4.0 / dt) * v_ - a_;
  v_ += 0.5 * dt * (a_ + a_new);
  a_ = a_new;
  q_.swap(qs_);
  ++step_;
}

void VehiclePassage::record(PassageBlock& out) {
  out.time_s.push_back(time());
  for (int i = 0; i < nw_; ++i) {
    out.wheel_x_m.push_back(x_[i]);
    out.contact_force_n.push_back(F_[i]);
    out.unevenness_m.push_back(z_[i]);
    out.rail_displacement_m.push_back(w_rail_[i]);
    out.wheel_displacement_m.push_back(q_[model_.wheels()[i].contact_dof]);
  }
  if (options_.record_poses) {
    for (const auto& p : model_.poses(q_)) out.poses.push_back(p);
  }
  if (options_.record_ballast) {
    rail_->ballastForces(scratch_);
    out.ballast_force_n.insert(out.ballast_force_n.end(), scratch_.begin(), scratch_.end());
  }
}

size_t VehiclePassage::advance(size_t n, PassageBlock& out) {
  out.clear();
  out.first_index = emitted_;
  out.time_step_s = params_.time_step_s;
  out.wheel_count = nw_;
  out.body_count = static_cast<int>(model_.bodies().size());
  out.sleeper_count = static_cast<int>(rail_->sleeperPositions().size());
  out.rail_seat_count = rail_->railSeatCount();
  const uint64_t total = totalSamples();
  size_t produced = 0;
  while (produced < n && emitted_ < total) {
    if (emitted_ > 0) step();
    record(out);
    ++emitted_;
    ++produced;
  }
  return produced;
}

}  // namespace railvib::vehicle
