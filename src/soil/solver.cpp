#include "railvib/soil/solver.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "implicit_unit.hpp"
#include "inclusion_unit.hpp"
#include "rigid_body_unit.hpp"

namespace railvib::soil {

namespace {
// Below this many nodes per step the nodal update (< ~0.5 ms) does not pay for
// the OpenMP fork/join: run serially.
constexpr size_t kMinParallelNodes = 20000;
}  // namespace

size_t solverMemoryBytes(const StructuredMesh& mesh, Precision precision) {
  const size_t real = precision == Precision::Float ? sizeof(float) : sizeof(double);
  // u, v, w, f (3 each), va, vb (3 each), mass
  return mesh.nodeCount() * 19 * real + mesh.nz * 576 * real;
}

struct Solver::Impl {
  virtual ~Impl() = default;
  virtual void init(const StructuredMesh& m, const SolverOptions& o, double dt, const std::vector<double>& mass,
                    const std::vector<double> c[3]) = 0;
  virtual void setKernel(KernelKind kind, const ElementBox& box) = 0;
  /// Spread over ranks: the communicator and partition (before setKernel).
  virtual void setPartition(SoilComm* comm, const SlabPartition& partition) = 0;
  virtual void addUnit(const SoilBoundary& boundary, const BoundaryContext& bc) = 0;
  /// The unit of the mesh's material inclusions (inclusion_unit.hpp), after the boundary's; and, when some
  /// are implicit, the unit that solves their nodes (implicit_unit.hpp), built on the whole mesh.
  virtual void addInclusions(double soil_beta_s, const StructuredMesh& global_mesh) = 0;
  virtual double kernelMultiplyAdds() const = 0;
  virtual size_t attachRigidBody(const RigidBodySpec& spec, const StructuredMesh& global_mesh,
                                 const std::vector<double>& global_mass) = 0;
  virtual const RigidBodyState& rigidBody(size_t i) const = 0;
  virtual size_t rigidBodyCount() const = 0;
  virtual double unitEnergy() const = 0;
  virtual Solver::ImplicitSolveInfo implicitSolve() const = 0;
  virtual void step(const std::vector<ForceChannel>& ch, const std::vector<double>& values) = 0;
  virtual double get(int what, size_t node, int c) const = 0;  // 0 u, 1 v
  virtual void set(int what, size_t node, int c, double value) = 0;
  virtual void internalForce(std::vector<double>& out) = 0;
  virtual double kinetic(const std::vector<double>& mass) const = 0;
};

namespace {

template <class Real>
struct ImplT : Solver::Impl {
  const StructuredMesh* mesh = nullptr;
  size_t n = 0, sx = 0, sxy = 0;
  int threads = 1;
  Real dt = 0, beta = 0, e_filter = 0;
  // The damping filter's state beta vf is w - u: no array of its own (one read and one write stream
  // less per component in the memory-bound nodal update).
  std::vector<Real> u[3], v[3], w[3], f[3], va[3], vb[3];
  // One kernel on one rank; spread over ranks, the kernel in parts: first the forces on the shared planes
  // (they are sent), then the rest in pieces while the messages travel.
  std::unique_ptr<StiffnessKernel<Real>> kernel;
  SplitKernel<Real> split;
  SoilComm* comm = nullptr;  // null on one rank
  SlabPartition partition;
  std::vector<Real> send_low, send_high, recv_low, recv_high;
  std::vector<std::unique_ptr<SolverUnit<Real>>> units;
  std::vector<const RigidBodyCore*> bodies;
  const InclusionUnit<Real>* inclusions = nullptr;
  ImplicitUnit<Real>* implicit_unit = nullptr;
  StepContext<Real> ctx;

  void init(const StructuredMesh& m, const SolverOptions& o, double dt_s, const std::vector<double>& mass,
            const std::vector<double> c[3]) override {
    mesh = &m;
    n = m.nodeCount();
    sx = m.nx + 1;
    sxy = (m.nx + 1) * (m.ny + 1);
    dt = static_cast<Real>(dt_s);
    beta = static_cast<Real>(o.rayleigh_beta_s);
    e_filter = static_cast<Real>(std::exp(-2.0 * M_PI * o.damping_cutoff_hz * dt_s));
    threads = o.threads > 0 ? o.threads : omp_get_max_threads();
    // The depth slabs, hence the order of the float sums at the slab planes, follow the team size:
    // a runtime that shrinks teams under load (OMP_DYNAMIC) would make runs differ by round-off.
    omp_set_dynamic(0);
    for (int d = 0; d < 3; ++d) {
      u[d].assign(n, 0);
      v[d].assign(n, 0);
      w[d].assign(n, 0);
      f[d].assign(n, 0);
      va[d].resize(n);
      vb[d].resize(n);
      for (size_t i = 0; i < n; ++i) {
        const double a = mass[i] / dt_s;
        // A node with no mass lies inside a void (MeshSpec::inclusions): no element moves it.
        const bool fixed =
            mass[i] == 0.0 || (o.lateral_rollers && d < 2) || (o.fixed_bottom && i >= n - sxy) ||
            (o.symmetry_x_min && d == 0 && i % sx == 0) || (o.symmetry_y_min && d == 1 && (i % sxy) / sx == 0) ||
            (o.antisymmetry_x_min && d != 0 && i % sx == 0) || (o.antisymmetry_y_min && d != 1 && (i % sxy) / sx == 0);
        va[d][i] = fixed ? Real(0) : static_cast<Real>((a - 0.5 * c[d][i]) / (a + 0.5 * c[d][i]));
        vb[d][i] = fixed ? Real(0) : static_cast<Real>(1.0 / (a + 0.5 * c[d][i]));
      }
    }
    ctx.mesh = &m;
    ctx.mass = &mass;
    ctx.dt = dt;
    ctx.beta = beta;
    ctx.filter_decay = e_filter;
    ctx.threads = threads;
    ctx.fields.node_count = n;
    for (int d = 0; d < 3; ++d) {
      ctx.fields.u[d] = u[d].data();
      ctx.fields.v[d] = v[d].data();
      ctx.fields.w[d] = w[d].data();
      ctx.fields.f[d] = f[d].data();
      ctx.fields.va[d] = va[d].data();
      ctx.fields.vb[d] = vb[d].data();
    }
  }

  void setPartition(SoilComm* c, const SlabPartition& p) override {
    comm = p.single() ? nullptr : c;
    partition = p;
    const size_t plane = 3 * (mesh->ny + 1) * (mesh->nz + 1);
    if (partition.hasLow()) send_low.resize(plane), recv_low.resize(plane);
    if (partition.hasHigh()) send_high.resize(plane), recv_high.resize(plane);
  }

  void setKernel(KernelKind kind, const ElementBox& box) override {
    if (!comm) {
      kernel = makeStiffnessKernel<Real>(kind, *mesh, box, threads);
      return;
    }
    // A few pieces are enough for the exchange to finish behind the interior work.
    constexpr size_t kInteriorPieces = 4;
    split = makeSplitStiffnessKernel<Real>(kind, *mesh, box, threads, partition.hasLow(), partition.hasHigh(),
                                           kInteriorPieces);
  }

  // The shared node planes: local i = 0 (low neighbour) and i = nx (high neighbour), j fastest, then k.
  void packPlane(size_t i, Real* buf) const {
    size_t q = 0;
    for (size_t k = 0; k <= mesh->nz; ++k) {
      for (size_t j = 0; j <= mesh->ny; ++j) {
        const size_t nd = mesh->node(i, j, k);
        for (int d = 0; d < 3; ++d) buf[q++] = f[d][nd];
      }
    }
  }
  void addPlane(size_t i, const Real* buf) {
    size_t q = 0;
    for (size_t k = 0; k <= mesh->nz; ++k) {
      for (size_t j = 0; j <= mesh->ny; ++j) {
        const size_t nd = mesh->node(i, j, k);
        for (int d = 0; d < 3; ++d) f[d][nd] += buf[q++];
      }
    }
  }
  void addUnit(const SoilBoundary& boundary, const BoundaryContext& bc) override;
  void addInclusions(double soil_beta_s, const StructuredMesh& global_mesh) override {
    auto unit = std::make_unique<InclusionUnit<Real>>(*mesh, soil_beta_s, threads);
    inclusions = unit.get();
    units.push_back(std::move(unit));
    const bool any_implicit = std::any_of(global_mesh.inclusions.begin(), global_mesh.inclusions.end(),
                                          [](const MeshInclusion& inc) { return inc.implicit; });
    if (!any_implicit) return;
    auto solve = std::make_unique<ImplicitUnit<Real>>(
        global_mesh, static_cast<double>(dt), static_cast<double>(e_filter), static_cast<double>(beta), threads);
    if (comm) solve->spread(*mesh, partition, comm);
    implicit_unit = solve.get();
    units.push_back(std::move(solve));
  }

  double kernelMultiplyAdds() const override {
    return kernel ? kernel->multiplyAddsPerApply() : split.multiplyAddsPerApply();
  }

  size_t attachRigidBody(const RigidBodySpec& spec, const StructuredMesh& global_mesh,
                         const std::vector<double>& global_mass) override {
    if (ctx.step != 0) throw std::logic_error("soil solver: attach rigid bodies before the first step");
    if (implicit_unit) {
      // With implicit inclusions a body is advanced in their solve: its carried nodes may touch them (a house
      // on a meshed foundation), and a body apart costs that solve a few rows only.
      auto core = std::make_unique<RigidBodyCore>(global_mesh, global_mass, spec, static_cast<double>(dt),
                                                  static_cast<double>(e_filter), static_cast<double>(beta));
      bodies.push_back(core.get());
      implicit_unit->absorb(std::move(core));
      return bodies.size() - 1;
    }
    auto unit = std::make_unique<RigidBodyUnit<Real>>(global_mesh, global_mass, spec, static_cast<double>(dt),
                                                      static_cast<double>(e_filter), static_cast<double>(beta));
    if (comm) unit->spread(global_mesh, *mesh, partition, comm);
    bodies.push_back(&unit->core());
    units.push_back(std::move(unit));
    return bodies.size() - 1;
  }
  const RigidBodyState& rigidBody(size_t i) const override { return bodies.at(i)->state(); }
  size_t rigidBodyCount() const override { return bodies.size(); }
  Solver::ImplicitSolveInfo implicitSolve() const override {
    Solver::ImplicitSolveInfo info;
    if (!implicit_unit || !implicit_unit->core().ready()) return info;
    const ImplicitCore& core = implicit_unit->core();
    info.unknowns = core.unknowns();
    info.factor_nonzeros = core.factor().factorNonZeros();
    info.part_0 = core.factor().partSize(0);
    info.part_1 = core.factor().partSize(1);
    info.separator = core.factor().partSize(2);
    return info;
  }
  double unitEnergy() const override {
    double e = 0.0;
    for (const auto& unit : units) e += unit->energy(ctx);
    return e;
  }

  void step(const std::vector<ForceChannel>& ch, const std::vector<double>& values) override {
    const Real* in[3] = {w[0].data(), w[1].data(), w[2].data()};
    Real* out[3] = {f[0].data(), f[1].data(), f[2].data()};
    if (!comm) kernel->apply(in, out);
    for (const auto& k : split.faces) k->apply(in, out);
    for (auto& unit : units) unit->addForces(ctx);
    for (size_t c = 0; c < ch.size(); ++c) {
      const double val = values[c];
      if (val == 0.0) continue;
      for (size_t q = 0; q < ch[c].nodes.size(); ++q) {
        f[ch[c].components[q]][ch[c].nodes[q]] += static_cast<Real>(ch[c].weights[q] * val);
      }
    }
    if (comm) {
      // The shared planes hold this slab's part of their forces: send it, integrate the interior, add
      // the neighbours' parts.
      if (partition.hasLow()) packPlane(0, send_low.data());
      if (partition.hasHigh()) packPlane(mesh->nx, send_high.data());
      comm->startExchange(send_low.data(), recv_low.data(), send_low.size() * sizeof(Real), send_high.data(),
                          recv_high.data(), send_high.size() * sizeof(Real));
      for (const auto& k : split.rest) {
        k->apply(in, out);
        comm->progressExchange();
      }
      comm->finishExchange();
      if (partition.hasLow()) addPlane(0, recv_low.data());
      if (partition.hasHigh()) addPlane(mesh->nx, recv_high.data());
    }
    for (auto& unit : units) unit->readForces(ctx);
    updateNodes();
    for (auto& unit : units) unit->afterUpdate(ctx);
    ++ctx.step;
  }

  // Central difference with the diagonal damping semi-implicit; the damping filter; f cleared.
  // The filter state is read as beta vf_n = w_n - u_n and written into w_{n+1}: its float round-off is
  // that of w itself (eps |u|), damped by e each step.
  void updateNodes() {
    const Real beta_one_e = beta * (Real(1) - e_filter);
#pragma omp parallel num_threads(threads) if (threads > 1 && n >= kMinParallelNodes)
    for (int d = 0; d < 3; ++d) {
      Real* __restrict ud = u[d].data();
      Real* __restrict vd = v[d].data();
      Real* __restrict wd = w[d].data();
      Real* __restrict fd = f[d].data();
      const Real* __restrict vad = va[d].data();
      const Real* __restrict vbd = vb[d].data();
#pragma omp for simd schedule(static)
      for (size_t i = 0; i < n; ++i) {
        const Real u_old = ud[i];
        const Real filtered_old = wd[i] - u_old;  // beta vf_n
        const Real vn = vad[i] * vd[i] + vbd[i] * fd[i];
        vd[i] = vn;
        const Real un = u_old + dt * vn;
        ud[i] = un;
        wd[i] = un + (e_filter * filtered_old + beta_one_e * vn);
        fd[i] = 0;
      }
    }
  }

  double get(int what, size_t node, int c) const override {
    return static_cast<double>(what == 0 ? u[c][node] : v[c][node]);
  }
  void set(int what, size_t node, int c, double value) override {
    if (what == 0) {
      const Real filtered = w[c][node] - u[c][node];  // beta vf, kept
      u[c][node] = static_cast<Real>(value);
      w[c][node] = u[c][node] + filtered;
    } else {
      v[c][node] = static_cast<Real>(value);
    }
  }
  void internalForce(std::vector<double>& out_f) override {
    std::vector<Real> tmp[3];
    for (auto& t : tmp) t.assign(n, 0);
    const Real* in[3] = {u[0].data(), u[1].data(), u[2].data()};
    Real* out[3] = {tmp[0].data(), tmp[1].data(), tmp[2].data()};
    if (kernel) kernel->apply(in, out);
    for (const auto& k : split.faces) k->apply(in, out);
    for (const auto& k : split.rest) k->apply(in, out);
    if (inclusions) inclusions->addStiffness(in, out);
    out_f.resize(3 * n);
    for (size_t i = 0; i < n; ++i) {
      for (int d = 0; d < 3; ++d) out_f[3 * i + static_cast<size_t>(d)] = static_cast<double>(tmp[d][i]);
    }
  }
  double kinetic(const std::vector<double>& mass) const override {
    double e = 0;
    for (int d = 0; d < 3; ++d) {
      for (size_t i = 0; i < n; ++i) e += 0.5 * mass[i] * static_cast<double>(v[d][i]) * static_cast<double>(v[d][i]);
    }
    return e;
  }
};

template <>
void ImplT<float>::addUnit(const SoilBoundary& boundary, const BoundaryContext& bc) {
  if (auto unit = boundary.makeUnitFloat(bc)) units.push_back(std::move(unit));
}
template <>
void ImplT<double>::addUnit(const SoilBoundary& boundary, const BoundaryContext& bc) {
  if (auto unit = boundary.makeUnitDouble(bc)) units.push_back(std::move(unit));
}

}  // namespace

struct SolverExtra {
  std::vector<double> mass;
  std::vector<ForceChannel> channels;
  std::vector<double> values;
};

// Each element's mass to its 8 corners, with the element's own material (an inclusion's, none in a void).
static std::vector<double> lumpedMass(const StructuredMesh& m) {
  std::vector<double> mass(m.nodeCount(), 0.0);
  for (size_t k = 0; k < m.nz; ++k) {
    const double volume = m.hx * m.hy * (m.z[k + 1] - m.z[k]) / 8.0;
    const double me_level = m.levelMaterial(k).density_kg_m3 * volume;
    for (size_t j = 0; j < m.ny; ++j) {
      for (size_t i = 0; i < m.nx; ++i) {
        double me = me_level;
        if (!m.inclusions.empty()) {
          const Material* mat = m.elementMaterial(i, j, k);
          me = mat ? mat->density_kg_m3 * volume : 0.0;
        }
        for (size_t c = 0; c < 8; ++c) mass[m.node(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))] += me;
      }
    }
  }
  return mass;
}

namespace {
// The least element columns a slab needs: two, and an end slab the boundary layer along x plus one.
size_t endSlabColumns(const StructuredMesh& m, const SoilBoundary& boundary, const AbsorbingFaces& faces) {
  if (!(faces.x_min || faces.x_max)) return 2;
  const double zone = boundary.zoneThicknessM();
  return std::max<size_t>(2, static_cast<size_t>(std::floor(zone / m.hx + 1e-9)) + 1);
}
}  // namespace

Solver::Solver(StructuredMesh mesh, const SolverOptions& options, std::shared_ptr<SoilComm> comm)
    : global_mesh_(std::move(mesh)), options_(options), comm_(comm ? std::move(comm) : serialSoilComm()) {
  const StructuredMesh& g = global_mesh_;
  if (g.nx == 0 || g.ny == 0 || g.nz == 0) throw std::invalid_argument("soil solver: empty mesh");
  if (options_.ranks > 0 && options_.ranks != comm_->size()) {
    throw std::invalid_argument("soil.mesh.ranks = " + std::to_string(options_.ranks) + " but the soil runs on " +
                                std::to_string(comm_->size()) + " rank(s) (" + comm_->kind() +
                                "): start it with mpirun -np " + std::to_string(options_.ranks) +
                                ", or set soil.mesh.ranks: 0 to take the launcher's count");
  }
  if (options_.threads == 0 && comm_->size() > 1 && std::getenv("OMP_NUM_THREADS") == nullptr) {
    // threads: 0 means all cores; ranks on one host share them.
    options_.threads = std::max(1, omp_get_num_procs() / comm_->ranksOnThisHost());
  }
  boundary_ = makeSoilBoundary(options_.boundary);
  if (!g.inclusions.empty()) checkInclusionsInside(g, options.absorbing, *boundary_);
  partition_ =
      makeSlabPartition(g.nx, comm_->size(), comm_->rank(), 2, endSlabColumns(g, *boundary_, options_.absorbing));
  if (partition_.single()) {
    mesh_ = g;
  } else {
    // The slab's own faces along x are the shared planes (no boundary there), except at the ends of the box.
    mesh_ = sliceMesh(g, partition_.begin(), partition_.end());
    if (partition_.hasLow()) {
      options_.absorbing.x_min = false;
      options_.symmetry_x_min = options_.antisymmetry_x_min = false;
    }
    if (partition_.hasHigh()) options_.absorbing.x_max = false;
  }
  extra_ = std::make_unique<SolverExtra>();
  extra_->mass = lumpedMass(mesh_);
  const BoundaryContext bc{&mesh_, &extra_->mass, options_.absorbing};
  kernel_box_ = boundary_->kernelElements(bc);
  computeStabilityLimits();
  chooseStep();
  // The damping of the boundary is computed from the slab's own mass and faces (it is additive over
  // elements, like the mass); both are then summed over the shared planes.
  std::array<std::vector<double>, 3> c = diagonalDamping();
  if (!partition_.single()) {
    sumSharedPlanes(extra_->mass);
    for (auto& cc : c) sumSharedPlanes(cc);
  }
  if (options_.precision == Precision::Float) {
    impl_ = std::make_unique<ImplT<float>>();
  } else {
    impl_ = std::make_unique<ImplT<double>>();
  }
  impl_->init(mesh_, options_, dt_, extra_->mass, c.data());
  impl_->setPartition(comm_.get(), partition_);
  impl_->setKernel(options_.kernel, kernel_box_);
  impl_->addUnit(*boundary_, bc);
  if (!mesh_.inclusions.empty()) impl_->addInclusions(options_.rayleigh_beta_s, global_mesh_);
}

// A nodal quantity of the slab's elements summed with the neighbours' at the shared planes (set-up).
void Solver::sumSharedPlanes(std::vector<double>& values) const {
  const size_t plane = (mesh_.ny + 1) * (mesh_.nz + 1);
  std::vector<double> send_low, send_high, recv_low, recv_high;
  auto pack = [&](size_t i, std::vector<double>& buf) {
    buf.clear();
    for (size_t k = 0; k <= mesh_.nz; ++k) {
      for (size_t j = 0; j <= mesh_.ny; ++j) buf.push_back(values[mesh_.node(i, j, k)]);
    }
  };
  if (partition_.hasLow()) pack(0, send_low), recv_low.resize(plane);
  if (partition_.hasHigh()) pack(mesh_.nx, send_high), recv_high.resize(plane);
  comm_->startExchange(send_low.data(), recv_low.data(), send_low.size() * sizeof(double), send_high.data(),
                       recv_high.data(), send_high.size() * sizeof(double));
  comm_->finishExchange();
  auto add = [&](size_t i, const std::vector<double>& buf) {
    size_t q = 0;
    for (size_t k = 0; k <= mesh_.nz; ++k) {
      for (size_t j = 0; j <= mesh_.ny; ++j) values[mesh_.node(i, j, k)] += buf[q++];
    }
  };
  if (partition_.hasLow()) add(0, recv_low);
  if (partition_.hasHigh()) add(mesh_.nx, recv_high);
}

size_t Solver::localNode(size_t global_node) const {
  if (partition_.single()) return global_node;
  const StructuredMesh& g = global_mesh_;
  const size_t sx = g.nx + 1, sxy = sx * (g.ny + 1);
  const size_t i = global_node % sx, j = (global_node % sxy) / sx, k = global_node / sxy;
  if (k > g.nz || !partition_.holdsNodePlane(i)) return static_cast<size_t>(-1);
  return mesh_.node(i - partition_.begin(), j, k);
}

bool Solver::ownsPoint(double x_m) const {
  if (partition_.single()) return true;
  const StructuredMesh& g = global_mesh_;
  const double s = (x_m - g.x0) / g.hx;
  const size_t i = s <= 0.0 ? 0 : std::min(static_cast<size_t>(s), g.nx - 1);
  return partition_.ownerOfColumn(i) == partition_.rank;
}

// An inclusion is integrated with the kernel's elements, inside the boundary's zone and off the
// absorbing faces (their dashpots and layers are set from the level materials).
void checkInclusionsInside(const StructuredMesh& global, const AbsorbingFaces& faces, const SoilBoundary& boundary) {
  ElementBox inner = boundary.kernelElements(BoundaryContext{&global, nullptr, faces});
  // The boundary's zone (a damping layer integrated by the kernel too: the elements wholly in it; a PML's
  // are already outside the kernel's box), and at least one element.
  const double zone = boundary.zoneThicknessM();
  const size_t zx = std::max<size_t>(1, static_cast<size_t>(std::floor(zone / global.hx + 1e-6)));
  const size_t zy = std::max<size_t>(1, static_cast<size_t>(std::floor(zone / global.hy + 1e-6)));
  const AbsorbingFaces& f = faces;
  if (f.x_min) inner.i0 = std::max(inner.i0, zx);
  if (f.x_max) inner.i1 = std::min(inner.i1, global.nx > zx ? global.nx - zx : 0);
  if (f.y_min) inner.j0 = std::max(inner.j0, zy);
  if (f.y_max) inner.j1 = std::min(inner.j1, global.ny > zy ? global.ny - zy : 0);
  if (f.bottom) {
    const double floor_m = boundary.zoneAlongBottom() ? global.depth() - zone : global.depth();
    size_t k1 = 0;
    while (k1 + 1 < global.nz && global.z[k1 + 1] <= floor_m + 1e-9) ++k1;
    inner.k1 = std::min(inner.k1, k1);
  }
  for (const MeshInclusion& inc : global.inclusions) {
    const ElementBox& e = inc.elements;
    const struct {
      const char* axis;
      bool inside;
      double lo, hi, room_lo, room_hi;
    } axes[3] = {{"x", e.i0 >= inner.i0 && e.i1 <= inner.i1, global.x(e.i0), global.x(e.i1), global.x(inner.i0),
                  global.x(inner.i1)},
                 {"y", e.j0 >= inner.j0 && e.j1 <= inner.j1, global.y(e.j0), global.y(e.j1), global.y(inner.j0),
                  global.y(inner.j1)},
                 {"depth", e.k0 >= inner.k0 && e.k1 <= inner.k1, global.z[e.k0], global.z[e.k1], global.z[inner.k0],
                  global.z[inner.k1]}};
    for (const auto& a : axes) {
      if (a.inside) continue;
      std::ostringstream why;
      why << "soil inclusion '" << inc.name << "' spans " << a.axis << " [" << a.lo << ", " << a.hi
          << "] m as meshed, into the absorbing boundary (" << boundaryMethodName(boundary.method())
          << ") or onto an absorbing face: inclusions stay within " << a.axis << " [" << a.room_lo << ", " << a.room_hi
          << "] m; enlarge the soil box";
      throw InclusionError(why.str(), a.axis);
    }
  }
}

// Irons' element bound on lambda_max(M^-1 K) gives the undamped limit; the filtered Rayleigh damping and
// the boundary may lower it.
void Solver::computeStabilityLimits() {
  double lam = 0.0;
  for (size_t k = 0; k < mesh_.nz; ++k) {
    lam =
        std::max(lam, boxElementMaxEigenvalue(mesh_.hx, mesh_.hy, mesh_.z[k + 1] - mesh_.z[k], mesh_.levelMaterial(k)));
  }
  const double beta = options_.rayleigh_beta_s;
  const double omega_c = 2.0 * M_PI * options_.damping_cutoff_hz;
  // An inclusion's elements with their own material and Rayleigh coefficient (a void has none).
  double dt_inclusions = std::numeric_limits<double>::infinity();
  for (const MeshInclusion& inc : mesh_.inclusions) {
    // A void has no elements; an implicit inclusion's do not limit the step (implicit_unit.hpp).
    if (inc.is_void || inc.implicit) continue;
    const double beta_i = inc.rayleigh_beta_s >= 0.0 ? inc.rayleigh_beta_s : beta;
    for (size_t k = inc.elements.k0; k < inc.elements.k1; ++k) {
      const double lam_i = boxElementMaxEigenvalue(mesh_.hx, mesh_.hy, mesh_.z[k + 1] - mesh_.z[k], inc.material);
      lam = std::max(lam, lam_i);
      dt_inclusions = std::min(dt_inclusions, 2.0 / std::sqrt(lam_i) / std::sqrt(1.0 + beta_i * omega_c));
    }
  }
  const double omega_max = std::sqrt(lam);
  dt_undamped_ = 2.0 / omega_max;
  const BoundaryContext bc{&mesh_, &extra_->mass, options_.absorbing};
  dt_damped_ =
      std::min({dt_undamped_ / std::sqrt(1.0 + beta * omega_c), dt_inclusions, boundary_->stableStepLimitS(bc)});
  if (!partition_.single()) dt_damped_ = comm_->minimum(dt_damped_);
  const double xi = beta * omega_max / 2.0;
  dt_naive_ = dt_undamped_ * (std::sqrt(1.0 + xi * xi) - xi);
}

// The requested step if it is stable, else the safety fraction of the limit, aligned to the output rate.
void Solver::chooseStep() {
  if (options_.dt_s > 0.0) {
    if (options_.dt_s > dt_damped_) {
      throw std::invalid_argument("soil solver: dt " + std::to_string(options_.dt_s) + " s above the stability limit " +
                                  std::to_string(dt_damped_) + " s");
    }
    dt_ = options_.dt_s;
    return;
  }
  dt_ = options_.safety_factor * dt_damped_;
  if (options_.align_rate_hz > 0.0) {
    const double m = std::ceil(1.0 / (dt_ * options_.align_rate_hz) - 1e-9);
    dt_ = 1.0 / (m * options_.align_rate_hz);
  }
}

// Diagonal damping per node and component: the boundary's, then a uniform mass-proportional part.
std::array<std::vector<double>, 3> Solver::diagonalDamping() const {
  std::array<std::vector<double>, 3> c;
  for (auto& cc : c) cc.assign(mesh_.nodeCount(), 0.0);
  const BoundaryContext bc{&mesh_, &extra_->mass, options_.absorbing};
  boundary_->addNodalDamping(bc, c.data());
  if (options_.mass_damping_1_s > 0.0) {
    for (size_t nd = 0; nd < mesh_.nodeCount(); ++nd) {
      for (int d = 0; d < 3; ++d) c[d][nd] += options_.mass_damping_1_s * extra_->mass[nd];
    }
  }
  return c;
}

Solver::~Solver() = default;

size_t Solver::memoryBytes() const {
  return solverMemoryBytes(mesh_, options_.precision) + extra_->mass.size() * sizeof(double);
}

size_t Solver::addForceChannel(ForceChannel channel) {
  if (channel.nodes.size() != channel.components.size() || channel.nodes.size() != channel.weights.size()) {
    throw std::invalid_argument("soil solver: force channel with nodes, components and weights of different sizes");
  }
  if (!partition_.single()) {
    // This rank applies the loads of the node planes it owns (each node's load is applied once).
    ForceChannel mine;
    const size_t sx = global_mesh_.nx + 1;
    for (size_t q = 0; q < channel.nodes.size(); ++q) {
      if (!partition_.ownsNodePlane(channel.nodes[q] % sx)) continue;
      mine.nodes.push_back(localNode(channel.nodes[q]));
      mine.components.push_back(channel.components[q]);
      mine.weights.push_back(channel.weights[q]);
    }
    channel = std::move(mine);
  }
  for (size_t q = 0; q < channel.nodes.size(); ++q) {
    if (channel.nodes[q] >= mesh_.nodeCount() || channel.components[q] < 0 || channel.components[q] > 2) {
      throw std::invalid_argument("soil solver: force channel node " + std::to_string(channel.nodes[q]) +
                                  " / component " + std::to_string(channel.components[q]) + " outside the mesh");
    }
    if (extra_->mass[channel.nodes[q]] == 0.0 && channel.weights[q] != 0.0) {
      throw std::invalid_argument("soil solver: a load on node " + std::to_string(channel.nodes[q]) +
                                  ", inside a void of the soil (MeshSpec::inclusions): no soil there to carry it");
    }
  }
  extra_->channels.push_back(std::move(channel));
  extra_->values.push_back(0.0);
  return extra_->channels.size() - 1;
}

void Solver::setChannelValues(const std::vector<double>& values) {
  if (values.size() != extra_->values.size()) throw std::invalid_argument("soil solver: channel count mismatch");
  extra_->values = values;
}

void Solver::step() {
  impl_->step(extra_->channels, extra_->values);
  ++steps_;
}

double Solver::kernelMultiplyAddsPerStep() const { return impl_->kernelMultiplyAdds(); }

size_t Solver::attachRigidBody(const RigidBodySpec& spec) {
  // A body carries the soil of its region: a void there would leave it nodes without soil.
  const StructuredMesh& g = global_mesh_;
  for (const MeshInclusion& inc : g.inclusions) {
    const ElementBox& e = inc.elements;
    const bool overlaps = inc.is_void && g.x(e.i0) < spec.x_max_m && g.x(e.i1) > spec.x_min_m &&
                          g.y(e.j0) < spec.y_max_m && g.y(e.j1) > spec.y_min_m && g.z[e.k0] <= spec.depth_m;
    if (overlaps) {
      throw std::invalid_argument("soil solver: the void '" + inc.name + "' lies in the region of the rigid body '" +
                                  spec.name + "'");
    }
  }
  if (partition_.single()) return impl_->attachRigidBody(spec, global_mesh_, extra_->mass);
  // The body is the same on every rank (its nodes may lie in several slabs): built on the whole mesh.
  return impl_->attachRigidBody(spec, global_mesh_, lumpedMass(global_mesh_));
}
size_t Solver::rigidBodyCount() const { return impl_->rigidBodyCount(); }
const RigidBodyState& Solver::rigidBody(size_t index) const { return impl_->rigidBody(index); }
double Solver::unitEnergy() const { return impl_->unitEnergy(); }
Solver::ImplicitSolveInfo Solver::implicitSolve() const { return impl_->implicitSolve(); }

void Solver::run(uint64_t n) {
  for (uint64_t s = 0; s < n; ++s) step();
}

namespace {
size_t checkedLocal(const Solver& s, size_t node) {
  const size_t local = s.localNode(node);
  if (local >= s.localMesh().nodeCount()) {
    throw std::out_of_range("soil solver: node " + std::to_string(node) + " is not in the slab of rank " +
                            std::to_string(s.partition().rank));
  }
  return local;
}
}  // namespace

double Solver::displacement(size_t node, int c) const { return impl_->get(0, checkedLocal(*this, node), c); }
double Solver::velocity(size_t node, int c) const { return impl_->get(1, checkedLocal(*this, node), c); }
void Solver::setDisplacement(size_t node, int c, double value) { impl_->set(0, checkedLocal(*this, node), c, value); }
void Solver::setVelocity(size_t node, int c, double value) { impl_->set(1, checkedLocal(*this, node), c, value); }
double Solver::nodalMass(size_t node) const { return extra_->mass[checkedLocal(*this, node)]; }
double Solver::kineticEnergy() const {
  if (partition_.single()) return impl_->kinetic(extra_->mass);
  std::vector<double> owned = extra_->mass;  // the shared planes count once, on their owner
  if (partition_.hasHigh()) {
    for (size_t k = 0; k <= mesh_.nz; ++k) {
      for (size_t j = 0; j <= mesh_.ny; ++j) owned[mesh_.node(mesh_.nx, j, k)] = 0.0;
    }
  }
  return impl_->kinetic(owned);
}
void Solver::internalForce(std::vector<double>& f_out) const { impl_->internalForce(f_out); }

namespace {
struct Trilinear {
  size_t node[8];
  double weight[8];
};

Trilinear locate(const StructuredMesh& m, double x, double y, double d) {
  auto clampIndex = [](double s, size_t n) {
    if (s <= 0.0) return std::pair<size_t, double>{0, 0.0};
    if (s >= static_cast<double>(n)) return std::pair<size_t, double>{n - 1, 1.0};
    const size_t i = static_cast<size_t>(s);
    return std::pair<size_t, double>{i, s - static_cast<double>(i)};
  };
  const auto [i, fx] = clampIndex((x - m.x0) / m.hx, m.nx);
  const auto [j, fy] = clampIndex((y - m.y0) / m.hy, m.ny);
  size_t k = static_cast<size_t>(std::upper_bound(m.z.begin(), m.z.end(), d) - m.z.begin());
  k = std::min(std::max<size_t>(k, 1), m.nz) - 1;
  const double fz = std::clamp((d - m.z[k]) / (m.z[k + 1] - m.z[k]), 0.0, 1.0);
  Trilinear t;
  for (size_t c = 0; c < 8; ++c) {
    const size_t a = c & 1, b = (c >> 1) & 1, e = (c >> 2) & 1;
    t.node[c] = m.node(i + a, j + b, k + e);
    t.weight[c] = (a ? fx : 1 - fx) * (b ? fy : 1 - fy) * (e ? fz : 1 - fz);
  }
  return t;
}
}  // namespace

void Solver::velocityAt(double x, double y, double d, double out[3]) const {
  const Trilinear t = locate(mesh_, x, y, d);
  for (int c = 0; c < 3; ++c) {
    out[c] = 0.0;
    for (size_t q = 0; q < 8; ++q) out[c] += t.weight[q] * impl_->get(1, t.node[q], c);
  }
}

void Solver::displacementAt(double x, double y, double d, double out[3]) const {
  const Trilinear t = locate(mesh_, x, y, d);
  for (int c = 0; c < 3; ++c) {
    out[c] = 0.0;
    for (size_t q = 0; q < 8; ++q) out[c] += t.weight[q] * impl_->get(0, t.node[q], c);
  }
}

void Solver::surfaceVelocity(int component, std::vector<double>& out) const {
  if (component < 0 || component > 2) throw std::invalid_argument("Solver::surfaceVelocity: component not 0, 1 or 2");
  const StructuredMesh& g = global_mesh_;
  if (partition_.single()) {
    const size_t ns = (g.nx + 1) * (g.ny + 1);
    out.resize(ns);
    for (size_t i = 0; i < ns; ++i) out[i] = impl_->get(1, i, component);
    return;
  }
  out.assign((g.nx + 1) * (g.ny + 1), 0.0);
  const size_t b = partition_.begin();
  for (size_t j = 0; j <= g.ny; ++j) {
    for (size_t i = b; i <= partition_.end(); ++i) {
      if (partition_.ownsNodePlane(i)) out[g.node(i, j, 0)] = impl_->get(1, mesh_.node(i - b, j, 0), component);
    }
  }
}

}  // namespace railvib::soil
