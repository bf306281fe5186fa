// railvib/soil: the implicit inclusions' solve (implicit_unit.hpp).
#include "implicit_unit.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace railvib::soil {

ImplicitCore::ImplicitCore(const StructuredMesh& mesh, double dt_s, double filter_decay, double beta_s, int threads)
    : mesh_(mesh), dt_(dt_s), e_(filter_decay), beta_(beta_s), threads_(threads) {
  std::vector<const MeshInclusion*> implicit;
  for (const MeshInclusion& inc : mesh.inclusions) {
    if (!inc.implicit) continue;
    if (inc.is_void) throw std::invalid_argument("soil inclusion '" + inc.name + "': a void cannot be implicit");
    if (!(inc.rayleigh_beta_s >= 0.0)) {
      throw std::invalid_argument("soil inclusion '" + inc.name +
                                  "': an implicit inclusion needs its own Rayleigh coefficient (0 or more)");
    }
    implicit.push_back(&inc);
  }
  // Every matrix first (the elements point into them), then the elements.
  level_stiffness_.resize(implicit.size() * mesh.nz);
  for (size_t q = 0; q < implicit.size(); ++q) {
    const MeshInclusion& inc = *implicit[q];
    for (size_t k = inc.elements.k0; k < inc.elements.k1; ++k) {
      const auto ke = boxElementStiffness(mesh.hx, mesh.hy, mesh.z[k + 1] - mesh.z[k], inc.material.lambda(),
                                          inc.material.shearModulus());
      level_stiffness_[q * mesh.nz + k].assign(ke.begin(), ke.end());
    }
  }
  std::vector<size_t> corners;
  for (size_t q = 0; q < implicit.size(); ++q) {
    const ElementBox& b = implicit[q]->elements;
    for (size_t k = b.k0; k < b.k1; ++k) {
      for (size_t j = b.j0; j < b.j1; ++j) {
        for (size_t i = b.i0; i < b.i1; ++i) {
          Element e;
          for (size_t c = 0; c < 8; ++c) {
            e.node[c] = mesh.node(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
            corners.push_back(e.node[c]);
          }
          e.stiffness = level_stiffness_[q * mesh.nz + k].data();
          e.beta_s = implicit[q]->rayleigh_beta_s;
          elements_.push_back(e);
        }
      }
    }
  }
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  nodes_ = corners;
  implicit_nodes_ = nodes_.size();
  carried_.assign(nodes_.size(), Carried{});
  // Elements by node position in nodes_ (sorted).
  for (Element& e : elements_) {
    for (size_t& nd : e.node) {
      nd = static_cast<size_t>(std::lower_bound(nodes_.begin(), nodes_.end(), nd) - nodes_.begin());
    }
  }
}

void ImplicitCore::absorb(std::unique_ptr<RigidBodyCore> body) {
  if (ready_) throw std::logic_error("soil solver: attach rigid bodies before the first step");
  const int b = static_cast<int>(bodies_.size());
  const std::vector<size_t>& carried = body->nodes();
  for (size_t a = 0; a < carried.size(); ++a) {
    const auto end = nodes_.begin() + static_cast<long>(implicit_nodes_);
    const auto it = std::lower_bound(nodes_.begin(), end, carried[a]);
    size_t p = 0;
    if (it != end && *it == carried[a]) {
      p = static_cast<size_t>(it - nodes_.begin());
    } else {
      p = nodes_.size();
      nodes_.push_back(carried[a]);
      carried_.push_back(Carried{});
    }
    if (carried_[p].body >= 0) {
      throw std::invalid_argument("rigid body '" + body->spec().name + "' carries a node another body carries");
    }
    carried_[p] = Carried{b, a};
  }
  bodies_.push_back(std::move(body));
}

void ImplicitCore::terms(size_t p, int c, std::vector<Term>& out) const {
  out.clear();
  const Carried& cr = carried_[p];
  if (cr.body < 0) {
    const int d = dof_[3 * p + static_cast<size_t>(c)];
    if (d >= 0) out.push_back({d, 1.0});
    return;
  }
  // u_a = u + w x r = u - r x w: row c of R_a = [I, -S(r)].
  const RigidBodyCore& body = *bodies_[static_cast<size_t>(cr.body)];
  const Eigen::Vector3d& r = body.offsets()[cr.index];
  double row[6] = {0, 0, 0, 0, 0, 0};
  row[c] = 1.0;
  const double skew[3][3] = {{0.0, r.z(), -r.y()}, {-r.z(), 0.0, r.x()}, {r.y(), -r.x(), 0.0}};
  for (int j = 0; j < 3; ++j) row[3 + j] = skew[c][j];
  const std::vector<int>& active = body.activeDofs();
  for (size_t q = 0; q < active.size(); ++q) {
    if (active[q] < 6 && row[active[q]] != 0.0) {
      out.push_back({body_offset_[static_cast<size_t>(cr.body)] + static_cast<int>(q), row[active[q]]});
    }
  }
}

void ImplicitCore::initialise(const std::vector<double>& values) {
  const size_t n = nodes_.size();
  if (values.size() != 15 * n) throw std::logic_error("implicit inclusions: node values of the wrong size");
  dof_.assign(3 * n, -1);
  int count = 0;
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> damping;
  for (size_t p = 0; p < n; ++p) {
    if (carried_[p].body >= 0) continue;
    for (int c = 0; c < 3; ++c) {
      const double va = values[15 * p + static_cast<size_t>(c)], vb = values[15 * p + 3 + static_cast<size_t>(c)];
      if (va == 0.0 && vb == 0.0) continue;  // held (a symmetry plane, a fixed bottom)
      dof_[3 * p + static_cast<size_t>(c)] = count;
      // v+ = va v- + vb f is (M/dt + C/2) v+ = (M/dt - C/2) v- + f with 1/vb = M/dt + C/2, va/vb = M/dt - C/2.
      t.emplace_back(count, count, 1.0 / vb);
      damping.push_back((1.0 - va) / vb);
      ++count;
    }
  }
  body_offset_.clear();
  for (const auto& body : bodies_) {
    body_offset_.push_back(count);
    const std::vector<int>& active = body->activeDofs();
    const Eigen::MatrixXd& mc = body->coupledMass();
    const Eigen::VectorXd& c = body->dampingDiagonal();
    for (size_t r = 0; r < active.size(); ++r) {
      for (size_t q = 0; q < active.size(); ++q) {
        double a = mc(active[r], active[q]) / dt_;
        if (r == q) a += 0.5 * c[active[r]];
        if (a != 0.0) t.emplace_back(count + static_cast<int>(r), count + static_cast<int>(q), a);
      }
      damping.push_back(c[active[r]]);
    }
    count += static_cast<int>(active.size());
  }
  // (dt/4 + beta/2) K_I, each element's rows and columns through the terms of its nodal components; the
  // damping beta K_I apart too, for the right-hand side.
  std::vector<Term> tr, tq;
  std::vector<Eigen::Triplet<double>> td;
  for (const Element& e : elements_) {
    for (int r = 0; r < 24; ++r) {
      terms(e.node[r / 3], r % 3, tr);
      if (tr.empty()) continue;
      for (int q = 0; q < 24; ++q) {
        const double k = e.stiffness[r * 24 + q];
        if (k == 0.0) continue;
        terms(e.node[q / 3], q % 3, tq);
        for (const Term& a : tr) {
          for (const Term& b : tq) {
            const double kab = k * a.coefficient * b.coefficient;
            t.emplace_back(a.unknown, b.unknown, (0.25 * dt_ + 0.5 * e.beta_s) * kab);
            if (e.beta_s > 0.0) td.emplace_back(a.unknown, b.unknown, e.beta_s * kab);
          }
        }
      }
    }
  }
  stiffness_damping_.resize(count, count);
  stiffness_damping_.setFromTriplets(td.begin(), td.end());
  td.clear();
  td.shrink_to_fit();
  Eigen::SparseMatrix<double> matrix(count, count);
  matrix.setFromTriplets(t.begin(), t.end());
  std::vector<Eigen::Triplet<double>>().swap(t);  // released before the factorisation, the peak
  // One level of nested dissection for the two-thread substitutions: the node plane i_mid (the median
  // plane of the unknowns) and the bodies (their rings may reach both sides) separate the nodes below
  // it from those above, which share no element.
  std::vector<size_t> planes;
  for (size_t p = 0; p < n; ++p) {
    if (carried_[p].body < 0) planes.push_back(nodes_[p] % (mesh_.nx + 1));
  }
  size_t i_mid = 0;
  if (!planes.empty()) {
    std::nth_element(planes.begin(), planes.begin() + static_cast<long>(planes.size() / 2), planes.end());
    i_mid = planes[planes.size() / 2];
  }
  std::vector<int> part(static_cast<size_t>(count), 2);
  for (size_t p = 0; p < n; ++p) {
    const size_t i = nodes_[p] % (mesh_.nx + 1);
    for (size_t c = 0; c < 3; ++c) {
      const int d = dof_[3 * p + c];
      if (d >= 0) part[static_cast<size_t>(d)] = i < i_mid ? 0 : i > i_mid ? 1 : 2;
    }
  }
  if (!solver_.factor(matrix, part)) {
    throw std::invalid_argument("implicit inclusions: the step matrix M/dt + C/2 + dt/4 K is not positive definite");
  }
  damping_ = Eigen::Map<const Eigen::VectorXd>(damping.data(), static_cast<long>(damping.size()));
  z_ = Eigen::VectorXd::Zero(count);
  u_.assign(3 * n, 0.0);
  filtered_.assign(3 * n, 0.0);
  for (size_t p = 0; p < n; ++p) {
    for (size_t c = 0; c < 3; ++c) {
      u_[3 * p + c] = values[15 * p + 6 + c];
      filtered_[3 * p + c] = values[15 * p + 12 + c];
      if (dof_[3 * p + c] >= 0) z_[dof_[3 * p + c]] = values[15 * p + 9 + c];
    }
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const std::vector<int>& active = bodies_[b]->activeDofs();
    for (size_t r = 0; r < active.size(); ++r) {
      z_[body_offset_[b] + static_cast<int>(r)] = bodies_[b]->fullVelocity()[active[r]];
    }
  }
  rhs_.resize(count);
  ready_ = true;
}

void ImplicitCore::advance(const std::vector<double>& force, std::vector<double>& out) {
  const size_t n = nodes_.size();
  rhs_.setZero();
  generalised_.assign(bodies_.size(), Eigen::Matrix<double, 6, 1>::Zero());
  for (size_t p = 0; p < n; ++p) {
    const Eigen::Vector3d f(force[3 * p], force[3 * p + 1], force[3 * p + 2]);
    if (carried_[p].body >= 0) {
      const size_t b = static_cast<size_t>(carried_[p].body);
      bodies_[b]->addNodeForce(carried_[p].index, f, generalised_[b]);
      continue;
    }
    for (size_t c = 0; c < 3; ++c) {
      if (dof_[3 * p + c] >= 0) rhs_[dof_[3 * p + c]] = f[static_cast<long>(c)];
    }
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    RigidBodyCore& body = *bodies_[b];
    body.setForce(generalised_[b]);
    const Eigen::VectorXd& step_force = body.stepForce();
    const std::vector<int>& active = body.activeDofs();
    for (size_t r = 0; r < active.size(); ++r) rhs_[body_offset_[b] + static_cast<int>(r)] = step_force[active[r]];
  }
  // A v+ = (A - C) v- + f with C = C_nodal + beta K_I: the increment solves A (v+ - v-) = f - C v-.
  rhs_ -= damping_.cwiseProduct(z_);
  if (stiffness_damping_.nonZeros() > 0) rhs_.noalias() -= stiffness_damping_ * z_;
  solver_.solveInPlace(rhs_, threads_);
  z_ += rhs_;

  out.resize(9 * n);
  const double one_e = beta_ * (1.0 - e_);
  for (size_t p = 0; p < n; ++p) {
    if (carried_[p].body >= 0) continue;
    for (size_t c = 0; c < 3; ++c) {
      const size_t q = 3 * p + c;
      const double v = dof_[q] >= 0 ? z_[dof_[q]] : 0.0;
      u_[q] += dt_ * v;
      filtered_[q] = e_ * filtered_[q] + one_e * v;
      out[9 * p + c] = u_[q];
      out[9 * p + 3 + c] = v;
      out[9 * p + 6 + c] = u_[q] + filtered_[q];
    }
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    RigidBodyCore& body = *bodies_[b];
    body_velocity_.setZero(body.fullVelocity().size());
    const std::vector<int>& active = body.activeDofs();
    for (size_t r = 0; r < active.size(); ++r) body_velocity_[active[r]] = z_[body_offset_[b] + static_cast<int>(r)];
    body.commitVelocity(body_velocity_);
  }
  for (size_t p = 0; p < n; ++p) {
    if (carried_[p].body < 0) continue;
    const RigidBodyCore::NodeFields q = bodies_[static_cast<size_t>(carried_[p].body)]->nodeFields(carried_[p].index);
    for (size_t c = 0; c < 3; ++c) {
      out[9 * p + c] = q.u[static_cast<long>(c)];
      out[9 * p + 3 + c] = q.v[static_cast<long>(c)];
      out[9 * p + 6 + c] = q.w[static_cast<long>(c)];
    }
  }
}

double ImplicitCore::energy() const {
  double e = 0.0;
  for (const auto& body : bodies_) e += body->energy();
  return e;
}

}  // namespace railvib::soil
