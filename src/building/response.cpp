#include "railvib/building/response.hpp"

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "railvib/building/reduction.hpp"
#include "railvib/common/constants.hpp"

namespace railvib::building {
namespace {

// One-way: the foundation DOFs follow the bilinear interpolation in plan of the footprint
// receivers' motion, with the rotations of that interpolated field.
void bilinearFootprintMap(const BuildingModel& model, const std::vector<FootprintPoint>& footprint_,
                          const std::vector<int>& cd, std::vector<Eigen::Triplet<double>>& tp) {
  const BuildingParams& par = model.params();
  const int nx = par.footprint_nx, ny = par.footprint_ny;
  const double x0 = footprint_.front().x_building_m, x1 = footprint_.back().x_building_m;
  const double y0 = footprint_.front().y_building_m, y1 = footprint_.back().y_building_m;
  const double dx = (x1 - x0) / (nx - 1), dy = (y1 - y0) / (ny - 1);
  for (size_t r = 0; r < cd.size(); ++r) {
    const int node = cd[r] / 6, comp = cd[r] % 6;
    const Eigen::Vector3d& x = model.mesh().nodes[node];
    const int ix = std::clamp(static_cast<int>(std::floor((x.x() - x0) / dx)), 0, nx - 2);
    const int iy = std::clamp(static_cast<int>(std::floor((x.y() - y0) / dy)), 0, ny - 2);
    const double sx = (x.x() - x0) / dx - ix, sy = (x.y() - y0) / dy - iy;
    for (int cx = 0; cx < 2; ++cx) {
      for (int cy = 0; cy < 2; ++cy) {
        const int k = (iy + cy) * nx + (ix + cx);
        const double wx = cx ? sx : 1.0 - sx, wy = cy ? sy : 1.0 - sy;
        const double w = wx * wy;
        const double dwdx = (cx ? 1.0 : -1.0) / dx * wy, dwdy = (cy ? 1.0 : -1.0) / dy * wx;
        switch (comp) {
          case 0:
          case 1:
          case 2:
            tp.emplace_back(r, 3 * k + comp, w);
            break;
          case 3:  // rx = d uz / dy
            tp.emplace_back(r, 3 * k + 2, dwdy);
            break;
          case 4:  // ry = -d uz / dx
            tp.emplace_back(r, 3 * k + 2, -dwdx);
            break;
          default:  // rz = (d uy/dx - d ux/dy) / 2
            tp.emplace_back(r, 3 * k + 1, 0.5 * dwdx);
            tp.emplace_back(r, 3 * k + 0, -0.5 * dwdy);
        }
      }
    }
  }
}

}  // namespace

Eigen::MatrixXd footprintRigidFit(const BuildingParams& par) {
  const Eigen::Vector3d centre(0.5 * par.length_m, 0.5 * par.width_m, 0.0);
  const std::vector<FootprintPoint> footprint = footprintPoints(par);
  Eigen::MatrixXd a(3 * static_cast<Eigen::Index>(footprint.size()), 6);
  for (size_t k = 0; k < footprint.size(); ++k) {
    const Eigen::Vector3d r = Eigen::Vector3d(footprint[k].x_building_m, footprint[k].y_building_m, 0.0) - centre;
    a.block<3, 3>(3 * static_cast<Eigen::Index>(k), 0).setIdentity();
    a.block<3, 3>(3 * static_cast<Eigen::Index>(k), 3) << 0.0, r.z(), -r.y(), -r.z(), 0.0, r.x(), r.y(), -r.x(), 0.0;
  }
  return (a.transpose() * a).ldlt().solve(a.transpose());
}

namespace {

// Two-way: the foundation is rigid; its 6 DOFs (building frame, about the plan centre at the ground
// surface) are the least-squares fit of the footprint receivers' motion (exact for a rigid motion).
void rigidFoundationMap(const BuildingModel& model, const std::vector<int>& cd, Eigen::MatrixXd& fit,
                        std::vector<Eigen::Triplet<double>>& tp) {
  const BuildingParams& par = model.params();
  const Eigen::Vector3d centre(0.5 * par.length_m, 0.5 * par.width_m, 0.0);
  fit = footprintRigidFit(par);
  const Eigen::MatrixXd r = rigidMotionMap(model, centre);
  for (size_t q = 0; q < cd.size(); ++q) {
    for (int c = 0; c < 6; ++c) {
      if (r(cd[q], c) != 0.0) tp.emplace_back(static_cast<int>(q), c, r(cd[q], c));
    }
  }
}

}  // namespace

struct BuildingResponseSolver::Impl {
  int nf = 0;           // free DOFs
  int nq = 0;           // base motion coordinates: footprint components (one-way) or 6 rigid DOFs (two-way)
  Eigen::MatrixXd fit;  // two-way: rigid motion (6) from the footprint components (least squares)
  Eigen::SparseMatrix<double> kff;
  Eigen::VectorXd mff;
  Eigen::SparseMatrix<double, Eigen::RowMajor> p;                               // constrained DOF x footprint component
  Eigen::SparseMatrix<double> g;                                                // K_fc P
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> kllt;  // K_ff (quasi-static response)
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> keff;
  double keff_dt = -1.0;
  Eigen::VectorXd u, v, a, q, qd;
  std::vector<int> constrained_row;  // global DOF -> row of p (-1 if free)
};

BuildingResponseSolver::~BuildingResponseSolver() = default;

BuildingResponseSolver::BuildingResponseSolver(const BuildingModel& model, double sample_period_s)
    : model_(model),
      footprint_(footprintPoints(model.params())),
      points_(model.responseNodes()),
      sample_period_s_(sample_period_s),
      tracker_("footprint velocities"),
      impl_(std::make_unique<Impl>()) {
  if (!(sample_period_s > 0.0)) throw std::invalid_argument("building response: sample period must be positive");
  const BuildingParams& par = model.params();
  substeps_ = std::max(1, static_cast<int>(std::ceil(sample_period_s / par.max_time_step_s - 1e-9)));
  const RayleighCoefficients rayleigh = rayleighCoefficients(par);
  alpha_ = rayleigh.alpha_1_s;
  beta_ = rayleigh.beta_s;

  Impl& s = *impl_;
  const std::vector<int>& fi = model.freeIndex();
  const std::vector<int>& cd = model.constrainedDofs();
  s.nf = static_cast<int>(model.freeDofs().size());
  const bool rigid = par.coupling == SoilCoupling::TwoWay;
  s.nq = rigid ? 6 : static_cast<int>(3 * footprint_.size());
  s.constrained_row.assign(model.dofCount(), -1);
  for (size_t r = 0; r < cd.size(); ++r) s.constrained_row[cd[r]] = static_cast<int>(r);

  std::vector<Eigen::Triplet<double>> tp;
  if (rigid) {
    rigidFoundationMap(model, cd, s.fit, tp);
  } else {
    bilinearFootprintMap(model, footprint_, cd, tp);
  }
  s.p.resize(static_cast<int>(cd.size()), s.nq);
  s.p.setFromTriplets(tp.begin(), tp.end());
  // Partition K.
  std::vector<Eigen::Triplet<double>> tff, tfc;
  const Eigen::SparseMatrix<double>& k = model.stiffness();
  for (int c = 0; c < k.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it) {
      const int r = fi[it.row()];
      if (r < 0) continue;
      if (fi[it.col()] >= 0)
        tff.emplace_back(r, fi[it.col()], it.value());
      else
        tfc.emplace_back(r, s.constrained_row[it.col()], it.value());
    }
  }
  s.kff.resize(s.nf, s.nf);
  s.kff.setFromTriplets(tff.begin(), tff.end());
  Eigen::SparseMatrix<double> kfc(s.nf, static_cast<int>(cd.size()));
  kfc.setFromTriplets(tfc.begin(), tfc.end());
  s.mff.resize(s.nf);
  for (int i = 0; i < s.nf; ++i) s.mff[i] = model.mass()[model.freeDofs()[i]];
  s.g = kfc * Eigen::SparseMatrix<double>(s.p);
  s.kllt.compute(s.kff);
  if (s.kllt.info() != Eigen::Success) throw std::runtime_error("building response: K_ff is not positive definite");
  reset();
}

void BuildingResponseSolver::reset() {
  Impl& s = *impl_;
  s.u = Eigen::VectorXd::Zero(s.nf);
  s.v = Eigen::VectorXd::Zero(s.nf);
  s.a = Eigen::VectorXd::Zero(s.nf);
  s.q = Eigen::VectorXd::Zero(s.nq);
  s.qd = Eigen::VectorXd::Zero(s.nq);
  tracker_ = SampleIndexTracker("footprint velocities");
}

void BuildingResponseSolver::addPoint(const NamedPoint& point) {
  if (tracker_.nextIndex() != 0) throw std::logic_error("building response: add points before the first block");
  points_.push_back(model_.snap(point));
}

std::vector<std::string> BuildingResponseSolver::outputColumnNames() const {
  std::vector<std::string> out;
  for (const ResponseNode& r : points_)
    for (const char* c : {"_vx", "_vy", "_vz"}) out.push_back(r.name + c);
  return out;
}

void BuildingResponseSolver::step(const Eigen::VectorXd& qd_new, double dt) {
  Impl& s = *impl_;
  // Newmark average acceleration (gamma = 1/2, beta = 1/4).
  const double a0 = 4.0 / (dt * dt), a1 = 2.0 / dt, a2 = 4.0 / dt;
  if (dt != s.keff_dt) {
    Eigen::SparseMatrix<double> ke = (1.0 + a1 * beta_) * s.kff;
    for (int i = 0; i < s.nf; ++i) ke.coeffRef(i, i) += (a0 + a1 * alpha_) * s.mff[i];
    s.keff.compute(ke);
    if (s.keff.info() != Eigen::Success) throw std::runtime_error("building response: factorisation failed");
    s.keff_dt = dt;
  }
  const Eigen::VectorXd q_new = s.q + 0.5 * dt * (s.qd + qd_new);
  // Loads from the foundation: elastic and damping coupling, and the mass-proportional
  // damping referred to the quasi-static motion.
  Eigen::VectorXd rhs = -(s.g * (q_new + beta_ * qd_new));
  if (alpha_ != 0.0) {
    const Eigen::VectorXd gqd = s.g * qd_new;
    const Eigen::VectorXd v_qs = -s.kllt.solve(gqd);  // quasi-static velocity of the free DOFs
    rhs += alpha_ * s.mff.cwiseProduct(v_qs);
  }
  const Eigen::VectorXd pm = a0 * s.u + a2 * s.v + s.a;  // a3 = 1
  const Eigen::VectorXd pc = a1 * s.u + s.v;             // a4 = 1, a5 = 0
  rhs += s.mff.cwiseProduct(pm) + alpha_ * s.mff.cwiseProduct(pc) + beta_ * (s.kff * pc);
  const Eigen::VectorXd u_new = s.keff.solve(rhs);
  const Eigen::VectorXd a_new = a0 * (u_new - s.u) - a2 * s.v - s.a;
  s.v += 0.5 * dt * (s.a + a_new);
  s.a = a_new;
  s.u = u_new;
  s.q = q_new;
  s.qd = qd_new;
}

Eigen::VectorXd BuildingResponseSolver::output() const {
  const Impl& s = *impl_;
  Eigen::VectorXd out(3 * points_.size());
  for (size_t i = 0; i < points_.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const int g = 6 * points_[i].node + c;
      const int f = model_.freeIndex()[g];
      if (f >= 0) {
        out[3 * i + c] = s.v[f];
      } else {
        double sum = 0.0;
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(s.p, s.constrained_row[g]); it; ++it)
          sum += it.value() * s.qd[it.col()];
        out[3 * i + c] = sum;
      }
    }
  }
  return out;
}

Eigen::MatrixXd BuildingResponseSolver::process(uint64_t first_sample, const Eigen::MatrixXd& vin) {
  if (vin.cols() != static_cast<Eigen::Index>(inputColumns()))
    throw std::invalid_argument("building response: expected " + std::to_string(inputColumns()) +
                                " footprint velocity columns, got " + std::to_string(vin.cols()));
  tracker_.accept(first_sample, static_cast<uint64_t>(vin.rows()));
  Eigen::MatrixXd out(vin.rows(), 3 * points_.size());
  const double dt = sample_period_s_ / substeps_;
  for (Eigen::Index r = 0; r < vin.rows(); ++r) {
    const Eigen::VectorXd start = impl_->qd;
    const Eigen::VectorXd target = impl_->fit.size() > 0 ? Eigen::VectorXd(impl_->fit * vin.row(r).transpose())
                                                         : Eigen::VectorXd(vin.row(r).transpose());
    for (int k = 1; k <= substeps_; ++k) step(start + (target - start) * (double(k) / substeps_), dt);
    out.row(r) = output().transpose();
  }
  return out;
}

TransferFunctions impulseTransferFunctions(const BuildingModel& model, const TransferFunctionOptions& opt) {
  BuildingResponseSolver solver(model, opt.sample_period_s);
  const int n = static_cast<int>(std::lround(opt.duration_s / opt.sample_period_s));
  const int cols = static_cast<int>(solver.inputColumns());
  TransferFunctions r;
  for (const ResponseNode& p : solver.responsePoints()) r.names.push_back(p.name);
  r.base_velocity = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd vin = Eigen::MatrixXd::Zero(n, cols);
  const double pi = 0.5 * kTwoPi;
  for (int i = 0; i < n; ++i) {
    const double t = (i + 1) * opt.sample_period_s;  // sample 0 is the first step after rest
    if (t < opt.pulse_duration_s) r.base_velocity[i] = std::sin(pi * t / opt.pulse_duration_s);
    for (size_t k = 0; k < solver.footprint().size(); ++k) vin(i, 3 * k + 2) = r.base_velocity[i];
  }
  const Eigen::MatrixXd out = solver.process(0, vin);
  const int np = static_cast<int>(r.names.size());
  r.response_velocity.resize(n, np);
  for (int p = 0; p < np; ++p) r.response_velocity.col(p) = out.col(3 * p + 2);
  const int nfreq = static_cast<int>(std::floor(opt.fmax_hz / opt.df_hz)) + 1;
  r.tf.resize(nfreq, np);
  for (int j = 0; j < nfreq; ++j) {
    const double f = j * opt.df_hz;
    r.frequency_hz.push_back(f);
    std::complex<double> base(0.0, 0.0);
    Eigen::VectorXcd resp = Eigen::VectorXcd::Zero(np);
    for (int i = 0; i < n; ++i) {
      const double t = (i + 1) * opt.sample_period_s;
      const std::complex<double> e = std::polar(1.0, -kTwoPi * f * t);
      base += r.base_velocity[i] * e;
      for (int p = 0; p < np; ++p) resp[p] += r.response_velocity(i, p) * e;
    }
    for (int p = 0; p < np; ++p) r.tf(j, p) = resp[p] / base;
  }
  return r;
}

}  // namespace railvib::building
