// The soil spread over MPI ranks (docs/soil.md, "MPI ranks"): run under mpirun with 2 ranks
// (CTest: mpirun -np 2 --oversubscribe). Every rank runs the spread solver; rank 0 also runs the same
// problem on one rank (no MPI) as the reference and makes the assertions.
//
// What the decomposition changes: the shared node plane between the two slabs receives the forces of
// its two element columns as two partial sums (one per rank) added afterwards, where one rank adds them
// element by element. Floating-point addition is not associative, so that plane rounds differently and
// the difference propagates: 1 vs 2 ranks agree to float round-off, bounded as the thread test does
// (test/unit/soil/test_soil_threads.cpp): kSteps * 2^-24 * peak, against the double-precision run of
// the same problem (the exact result at this scale). A lost, doubled or misplaced force at the cut, a
// load applied by both ranks or a boundary damping counted twice shows at 1e-3..1 of the peak.
// With a fixed decomposition the run is a fixed sequence of operations: bitwise reproducible.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "../unit/soil/soil_test_util.hpp"
#include "railvib/common/config.hpp"
#include "railvib/soil/partition.hpp"
#include "railvib/soil/soil_comm.hpp"
#include "railvib/soil/soil_driver.hpp"
#include "railvib/soil/soil_model.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/solver.hpp"

using namespace railvib::soil;
using railvib::soil::testing::maxAbs;
using railvib::soil::testing::maxAbsDiff;

namespace {

std::shared_ptr<SoilComm> g_world;

constexpr size_t kNx = 48, kNy = 40;
constexpr int kSteps = 300;
constexpr size_t kCut = kNx / 2;  // 2 balanced slabs: element columns [0, 24) and [24, 48)

// Haren layers 1-2 over a half-space, 0.25 m in plane, 20 levels: 48 x 40 x 20 = 38 400 elements.
StructuredMesh layeredMesh() { return railvib::soil::testing::layeredTestMesh(kNx, kNy); }

// Across the cut (column 24), off the 2 m graded layer (columns and rows 8..40 / 8..32): an open trench
// (columns 16..32, rows 22..24, 1 m deep) and a buried concrete wall damped by its own Rayleigh
// coefficient (columns 18..30, rows 9..11, depth 0.4-2.1 m), or integrated implicitly and undamped.
StructuredMesh meshWithInclusions(bool implicit_wall) {
  StructuredMesh m = layeredMesh();
  InclusionSpec trench;
  trench.name = "trench";
  trench.is_void = true;
  trench.x_min_m = -6.0 + 16 * 0.25, trench.x_max_m = -6.0 + 32 * 0.25;
  trench.y_min_m = -5.0 + 22 * 0.25, trench.y_max_m = -5.0 + 24 * 0.25;
  trench.top_m = 0.0, trench.bottom_m = 1.0;
  InclusionSpec wall = trench;
  wall.name = "wall";
  wall.is_void = false;
  wall.material = {20.0e9, 2400.0, 0.2};
  wall.rayleigh_beta_s = 1.0e-5;
  wall.x_min_m = -6.0 + 18 * 0.25, wall.x_max_m = -6.0 + 30 * 0.25;
  wall.y_min_m = -5.0 + 9 * 0.25, wall.y_max_m = -5.0 + 11 * 0.25;
  wall.top_m = 0.4, wall.bottom_m = 2.1;
  if (implicit_wall) {
    wall.implicit = true;
    wall.rayleigh_beta_s = 0.0;
  }
  addInclusions(m, {trench, wall}, 1e-9);
  return m;
}

struct Case {
  BoundaryMethod boundary = BoundaryMethod::GradedLayer;
  KernelKind kernel = KernelKind::Element;
  Precision precision = Precision::Float;
  bool rigid_body = false;
  bool inclusions = false;
  bool implicit = false;  // the wall implicit and the rigid body a one-element ring on its top face
};

SolverOptions options(const Case& c) {
  SolverOptions o;
  o.threads = 1;
  o.precision = c.precision;
  o.kernel = c.kernel;
  o.rayleigh_beta_s = 4.0e-4;  // the damping filter path too
  o.boundary.method = c.boundary;
  if (c.boundary == BoundaryMethod::GradedLayer) o.boundary.graded_layer = {2.0, 60.0, 1.0, false};
  if (c.boundary == BoundaryMethod::Pml) {
    o.boundary.pml.thickness_m = 1.5;
    o.boundary.pml.alpha_1_s = 10.0;
    o.boundary.pml.perpendicular_ratio = 0.05;
  }
  return o;
}

// A massive surface foundation across the cut (columns 20..28, the shared plane 24 in the middle).
RigidBodySpec foundation(bool ring) {
  RigidBodySpec b;
  b.x_min_m = -6.0 + 20 * 0.25;
  b.x_max_m = -6.0 + 28 * 0.25;
  b.y_min_m = -5.0 + 5 * 0.25;
  b.y_max_m = -5.0 + 11 * 0.25;
  b.depth_m = 0.4;
  b.reference_m = Eigen::Vector3d(0.5 * (b.x_min_m + b.x_max_m), 0.5 * (b.y_min_m + b.y_max_m), 0.0);
  const double m = 4.0e3;
  b.added_mass.diagonal() << m, m, m, 1.5e3, 2.5e3, 3.0e3;
  if (ring) b.ring_width_m = 0.25;
  return b;
}

struct Result {
  std::vector<double> surface_history;   // surface v_d of every node, every step
  std::vector<double> final_u, final_v;  // every node, 3 components
  double kinetic_j = 0.0;
  std::vector<double> body;  // rigid body displacement and velocity (12 values)
};

// The field of the whole mesh on rank 0: every rank contributes the nodes it owns, zeros elsewhere.
std::vector<double> gatherNodes(const Solver& s, bool displacement) {
  const StructuredMesh& m = s.mesh();
  std::vector<double> out(3 * m.nodeCount(), 0.0);
  for (size_t n = 0; n < m.nodeCount(); ++n) {
    if (!s.ownsNodePlane(n % (m.nx + 1))) continue;
    for (int c = 0; c < 3; ++c) out[3 * n + c] = displacement ? s.displacement(n, c) : s.velocity(n, c);
  }
  s.comm().sumToRoot(out.data(), out.size());
  return out;
}

// Loads: one patch on the shared plane (columns 22..26), one in each slab.
Result run(const Case& c, std::shared_ptr<SoilComm> comm) {
  Solver s(c.inclusions ? meshWithInclusions(c.implicit) : layeredMesh(), options(c), std::move(comm));
  if (c.rigid_body) s.attachRigidBody(foundation(c.implicit));
  const StructuredMesh& m = s.mesh();
  const size_t patches[3][2] = {{22, 18}, {10, 12}, {34, 26}};
  for (const auto& p : patches) {
    ForceChannel ch;
    for (size_t j = p[1]; j <= p[1] + 3; ++j) {
      for (size_t i = p[0]; i <= p[0] + 4; ++i) {
        ch.nodes.push_back(m.node(i, j, 0));
        ch.components.push_back(2);
        ch.weights.push_back(1.0 / 20.0);
      }
    }
    s.addForceChannel(ch);
  }
  Result r;
  std::vector<double> surf;
  for (int n = 0; n < kSteps; ++n) {
    const double t = s.time();
    const double hann = t < 0.025 ? 0.5 - 0.5 * std::cos(2.0 * M_PI * t / 0.025) : 0.0;
    s.setChannelValues({3.0e4 * hann * std::sin(2.0 * M_PI * 40.0 * t),
                        1.0e4 * std::min(1.0, t / 0.02) * std::sin(2.0 * M_PI * 15.0 * t + 0.3),
                        -0.8e4 * std::min(1.0, t / 0.01) * std::sin(2.0 * M_PI * 25.0 * t)});
    s.step();
    s.surfaceVelocity(2, surf);
    s.comm().sumToRoot(surf.data(), surf.size());
    r.surface_history.insert(r.surface_history.end(), surf.begin(), surf.end());
  }
  r.final_u = gatherNodes(s, true);
  r.final_v = gatherNodes(s, false);
  r.kinetic_j = s.kineticEnergy();
  s.comm().sumToRoot(&r.kinetic_j, 1);
  if (c.rigid_body) {
    const RigidBodyState& b = s.rigidBody(0);
    r.body.assign(b.displacement.data(), b.displacement.data() + 6);
    r.body.insert(r.body.end(), b.velocity.data(), b.velocity.data() + 6);
  }
  return r;
}

bool bitwiseEqual(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// 2 ranks against 1 rank (float) and against 1 rank in double: within kSteps u peak, as 1 vs 2 threads.
void expectAgreesWithOneRank(const Case& c, const char* what) {
  const Result spread = run(c, g_world);
  if (!g_world->root()) return;  // the references and the checks are rank 0's
  const Result one = run(c, serialSoilComm());
  Case d = c;
  d.precision = Precision::Double;
  const Result exact = run(d, serialSoilComm());
  const double peak = maxAbs(exact.surface_history);
  ASSERT_GT(peak, 0.0);
  const double u = std::ldexp(1.0, -24), tol = kSteps * u * peak;
  const double d21 = maxAbsDiff(spread.surface_history, one.surface_history);
  const double d2x = maxAbsDiff(spread.surface_history, exact.surface_history);
  const double d1x = maxAbsDiff(one.surface_history, exact.surface_history);
  std::printf(
      "%s: peak |v_surface| %.4e m/s; max |diff| / peak: 2 ranks vs 1 rank %.2e, 2 ranks vs double %.2e, "
      "1 rank vs double %.2e (tolerance %.2e); kinetic energy 2 ranks / 1 rank - 1 = %.2e\n",
      what, peak, d21 / peak, d2x / peak, d1x / peak, tol / peak, spread.kinetic_j / one.kinetic_j - 1.0);
  EXPECT_LE(d21, tol) << what << ": 2 ranks vs 1 rank";
  EXPECT_LE(d2x, tol) << what << ": 2 ranks vs double";
  if (!c.implicit) {
    EXPECT_LE(maxAbsDiff(spread.final_u, one.final_u), kSteps * u * maxAbs(exact.final_u)) << what;
    EXPECT_LE(maxAbsDiff(spread.final_v, one.final_v), kSteps * u * maxAbs(exact.final_v)) << what;
  } else {
    // Inside a stiff implicit inclusion the float force f_n - K u_n carries eps |K_I u|, the modulus
    // contrast times the soil's round-off, and the solve spreads it over the inclusion: its final
    // velocities sit ~1e-5 of the peak from double (the surface above stays at the soil's level). The
    // rank count must add nothing to that: 2 ranks as close to double as 1 rank is.
    for (std::vector<double> Result::*field : {&Result::final_u, &Result::final_v}) {
      const double one_off = maxAbsDiff(one.*field, exact.*field), spread_off = maxAbsDiff(spread.*field, exact.*field);
      std::printf("  final %s: max |diff| vs double, 1 rank %.2e, 2 ranks %.2e (field peak %.2e)\n",
                  field == &Result::final_u ? "u" : "v", one_off, spread_off, maxAbs(exact.*field));
      EXPECT_LE(spread_off, std::max(1.5 * one_off, kSteps * u * maxAbs(exact.*field))) << what;
    }
  }
  // The energy is a sum of squares over the owned nodes: the shared plane counted once.
  EXPECT_NEAR(spread.kinetic_j / one.kinetic_j, 1.0, 2.0 * kSteps * u) << what;
  if (c.rigid_body) {
    ASSERT_EQ(spread.body.size(), 12u);
    for (int q = 0; q < 12; ++q) {
      const double scale = std::max(std::abs(exact.body[q]), 1e-3 * maxAbs(exact.body));
      EXPECT_LE(std::abs(spread.body[q] - one.body[q]), kSteps * u * std::max(scale, 1e-30)) << what << " body " << q;
    }
    EXPECT_GT(maxAbs(exact.body), 0.0);
  }
}

}  // namespace

TEST(SoilMpi, RunsOnTwoRanksSplitAtTheMiddle) {
  ASSERT_EQ(g_world->size(), 2) << "run under mpirun -np 2";
  EXPECT_EQ(g_world->kind(), "mpi");
  Solver s(layeredMesh(), options({}), g_world);
  EXPECT_EQ(s.partition().cuts, (std::vector<size_t>{0, kCut, kNx}));
  EXPECT_EQ(s.localMesh().nx, kCut);
  EXPECT_EQ(s.localMesh().ny, kNy);
  EXPECT_EQ(s.mesh().nx, kNx);
  // The shared plane 24 is held by both and owned by rank 1.
  EXPECT_TRUE(s.partition().holdsNodePlane(kCut));
  EXPECT_EQ(s.ownsNodePlane(kCut), g_world->rank() == 1);
  // The lumped mass at the shared plane is the sum of both slabs' elements: the whole mesh's value.
  const Solver one(layeredMesh(), options({}), serialSoilComm());
  const size_t n = s.mesh().node(kCut, 7, 3);
  EXPECT_NEAR(s.nodalMass(n), one.nodalMass(n), 1e-12 * one.nodalMass(n));
  EXPECT_EQ(s.dt(), one.dt());
  EXPECT_THROW(s.nodalMass(s.mesh().node(g_world->rank() == 0 ? kNx : 0, 0, 0)), std::out_of_range);
}

TEST(SoilMpi, GradedLayerElementKernelAgreesWithOneRank) { expectAgreesWithOneRank({}, "graded layer, element"); }

TEST(SoilMpi, PmlStencilKernelAgreesWithOneRank) {
  expectAgreesWithOneRank({BoundaryMethod::Pml, KernelKind::Stencil, Precision::Float, false}, "PML, stencil");
}

TEST(SoilMpi, RigidBodyAcrossTheCutAgreesWithOneRank) {
  expectAgreesWithOneRank({BoundaryMethod::Dashpots, KernelKind::Element, Precision::Float, true},
                          "dashpots, element, rigid body across the cut");
}

TEST(SoilMpi, InclusionsAcrossTheCutAgreeWithOneRank) {
  for (KernelKind kernel : {KernelKind::Element, KernelKind::Stencil}) {
    expectAgreesWithOneRank({BoundaryMethod::GradedLayer, kernel, Precision::Float, false, true},
                            kernel == KernelKind::Element ? "graded layer, element, trench and wall across the cut"
                                                          : "graded layer, stencil, trench and wall across the cut");
  }
}

// The implicit system spans the cut: the wall's nodes on both slabs and a rigid ring absorbed into it.
TEST(SoilMpi, ImplicitWallAndRingAcrossTheCutAgreeWithOneRank) {
  expectAgreesWithOneRank({BoundaryMethod::GradedLayer, KernelKind::Element, Precision::Float, true, true, true},
                          "graded layer, element, implicit wall and rigid ring across the cut");
}

TEST(SoilMpi, FixedDecompositionIsBitwiseReproducible) {
  const Case c{BoundaryMethod::Pml, KernelKind::Element, Precision::Float, true};
  const Result a = run(c, g_world), b = run(c, g_world);
  if (!g_world->root()) return;
  ASSERT_GT(maxAbs(a.surface_history), 0.0);
  EXPECT_TRUE(bitwiseEqual(a.surface_history, b.surface_history));
  EXPECT_TRUE(bitwiseEqual(a.final_u, b.final_u));
  EXPECT_TRUE(bitwiseEqual(a.final_v, b.final_v));
  EXPECT_TRUE(bitwiseEqual(a.body, b.body));
}

TEST(SoilMpi, RankCountsThatDoNotFitAreRefused) {
  // soil.mesh.ranks disagreeing with the launcher.
  SolverOptions o = options({});
  o.ranks = 3;
  try {
    Solver s(layeredMesh(), o, g_world);
    ADD_FAILURE() << "no error for soil.mesh.ranks = 3 on 2 ranks";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("soil.mesh.ranks = 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mpirun -np 3"), std::string::npos) << e.what();
  }
  // More ranks than slabs: 48 columns, a 2 m (8 column) graded layer at each end needs 9 columns per end slab.
  EXPECT_NO_THROW(makeSlabPartition(kNx, 5, 0, 2, 9));
  try {
    makeSlabPartition(kNx, 40, 0, 2, 9);
    ADD_FAILURE() << "no error for 40 ranks on 48 columns";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("40 ranks"), std::string::npos) << e.what();
  }
  // Every node plane has exactly one owner, every column one rank.
  for (int ranks : {1, 2, 3, 5}) {
    std::vector<int> owners(kNx + 1, 0);
    for (int r = 0; r < ranks; ++r) {
      const SlabPartition p = makeSlabPartition(kNx, ranks, r, 2, 9);
      for (size_t i = 0; i <= kNx; ++i) owners[i] += p.ownsNodePlane(i) ? 1 : 0;
      for (size_t i = p.begin(); i < p.end(); ++i) EXPECT_EQ(p.ownerOfColumn(i), r);
    }
    for (size_t i = 0; i <= kNx; ++i) EXPECT_EQ(owners[i], 1) << ranks << " ranks, plane " << i;
  }
}

// The soil model on 2 ranks: receivers, surface snapshots and the section plane gathered on rank 0
// equal the one-rank model's to round-off; the loads of the sleepers on the cut counted once.
// A small scenario with three receivers and a section across the cut, and its sleeper loads.
struct SmallScenario {
  std::string yaml;
  SoilParams params;
  std::vector<double> sleeper_x_m = {-2.16, -1.44, -0.72, 0.0, 0.72, 1.44, 2.16};
  size_t frames = 201;
  std::vector<double> loads;

  static SoilParams paramsOf(const std::string& text) {
    return loadSoilParams(railvib::Config::fromString(text, "test.yaml").root());
  }
  SmallScenario() {
    yaml = railvib::soil::testing::smallScenario(
        "{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, poisson_ratio: 0.13}", "",
        "[{name: s2, x_m: 0.0, y_m: 2.0}, {name: s8, x_m: -3.0, y_m: 3.5}, {name: far, x_m: 3.2, y_m: -3.0}]");
    const std::string out = "output: {receiver_rate_hz: 1000.0, snapshot_rate_hz: 100.0}";
    yaml.replace(yaml.find(out), out.size(),
                 "output: {receiver_rate_hz: 1000.0, snapshot_rate_hz: 100.0, section: {x_m: 0.3}}");
    params = paramsOf(yaml);
    loads.resize(frames * sleeper_x_m.size());
    for (size_t f = 0; f < frames; ++f) {
      for (size_t s = 0; s < sleeper_x_m.size(); ++s) {
        loads[f * sleeper_x_m.size() + s] = 1e4 * std::exp(-std::pow((f / 2000.0 - 0.02 - 0.005 * s) / 0.004, 2));
      }
    }
  }
};

TEST(SoilMpi, SoilModelOutputsGatherOnRankZero) {
  const SmallScenario sc;
  const SoilParams& p = sc.params;
  const std::vector<double>& xs = sc.sleeper_x_m;
  const size_t frames = sc.frames;
  const std::vector<double>& loads = sc.loads;
  struct Outputs {
    std::vector<double> rec;
    std::vector<float> snaps, sections;
    size_t snap_count = 0, section_count = 0;
    std::string partition;
  };
  auto runModel = [&](std::shared_ptr<SoilComm> comm) {
    SoilModel m(p, xs, 2000.0, {}, std::move(comm));
    Outputs o;
    o.partition = m.summary()["partition"].get<std::string>();
    ReceiverBlock rb;
    std::vector<SurfaceSnapshot> snaps;
    std::vector<SectionSnapshot> sections;
    for (size_t f0 = 0; f0 < frames; f0 += 50) {
      const size_t nf = std::min<size_t>(50, frames - f0);
      m.pushLoads(f0, &loads[f0 * xs.size()], nf);
      m.advance(1e9);
      m.takeReceiverSamples(rb);
      o.rec.insert(o.rec.end(), rb.velocity_m_s.begin(), rb.velocity_m_s.end());
    }
    m.finishLoads();
    m.advance(0.1);
    m.finishOutputs();
    m.takeReceiverSamples(rb);
    o.rec.insert(o.rec.end(), rb.velocity_m_s.begin(), rb.velocity_m_s.end());
    m.takeSnapshots(snaps);
    m.takeSectionSnapshots(sections);
    // All three components (vx, vy, vz up), each summed over the ranks.
    for (const auto& s : snaps) {
      for (const auto* f : {&s.vx_m_s, &s.vy_m_s, &s.vz_up_m_s}) o.snaps.insert(o.snaps.end(), f->begin(), f->end());
    }
    for (const auto& s : sections) {
      for (const auto* f : {&s.vx_m_s, &s.vy_m_s, &s.vz_up_m_s}) {
        o.sections.insert(o.sections.end(), f->begin(), f->end());
      }
    }
    o.snap_count = snaps.size();
    o.section_count = sections.size();
    return o;
  };
  const Outputs spread = runModel(g_world);
  if (!g_world->root()) return;
  const Outputs one = runModel(serialSoilComm());
  std::printf("soil model partition: %s\n", spread.partition.c_str());
  EXPECT_NE(spread.partition.find("2 ranks"), std::string::npos) << spread.partition;
  ASSERT_EQ(spread.rec.size(), one.rec.size());
  ASSERT_GT(one.rec.size(), 3u * 3 * 90);
  ASSERT_EQ(spread.snap_count, one.snap_count);
  ASSERT_EQ(spread.section_count, one.section_count);
  ASSERT_GE(one.section_count, 9u);
  const double u = std::ldexp(1.0, -24);
  const double peak = maxAbs(one.rec);
  ASSERT_GT(peak, 0.0);
  // Steps of this model: 0.1 s / dt (a few hundred); the bound of the solver tests with that count.
  const double steps = 0.1 / SoilModel(p, xs, 2000.0).solver().dt();
  EXPECT_LE(maxAbsDiff(spread.rec, one.rec), steps * u * peak);
  auto floats = [](const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); };
  const std::vector<double> s_snap = floats(spread.snaps), o_snap = floats(one.snaps);
  const std::vector<double> s_sec = floats(spread.sections), o_sec = floats(one.sections);
  ASSERT_GT(maxAbs(o_snap), 0.0);
  ASSERT_GT(maxAbs(o_sec), 0.0);
  // Snapshots are floats: their own rounding (2^-24 of the value) on top.
  EXPECT_LE(maxAbsDiff(s_snap, o_snap), (steps + 1.0) * u * maxAbs(o_snap));
  EXPECT_LE(maxAbsDiff(s_sec, o_sec), (steps + 1.0) * u * maxAbs(o_sec));
}

// The soil node's way (docs/soil.md, "MPI ranks"): rank 0 alone drives a SoilDriver, the other ranks
// serve; every collective call must reach them in order, finishRun's slices included.
TEST(SoilMpi, DriverOnRankZeroAgreesWithOneRank) {
  const SmallScenario sc;
  const SoilDriver::Factory factory = [](const std::string& setup, const std::vector<double>& x,
                                         std::shared_ptr<SoilComm> comm) {
    return std::make_unique<SoilModel>(SmallScenario::paramsOf(setup), x, 2000.0, std::vector<RigidBodySpec>{},
                                       std::move(comm));
  };
  if (!g_world->root()) {
    EXPECT_EQ(SoilDriver::serve(g_world, factory), 0);
    return;
  }
  EXPECT_THROW(SoilDriver::serve(g_world, factory), std::logic_error);  // rank 0 drives
  std::vector<double> rec;
  size_t snaps = 0, sections = 0, slices = 0;
  std::string partition;
  {
    SoilDriver driver(g_world, factory);
    driver.create(sc.yaml, sc.sleeper_x_m);
    partition = driver.model().summary()["partition"].get<std::string>();
    ReceiverBlock rb;
    std::vector<SurfaceSnapshot> sn;
    std::vector<SectionSnapshot> se;
    auto take = [&] {
      driver.takeOutputs(rb, sn, se);
      rec.insert(rec.end(), rb.velocity_m_s.begin(), rb.velocity_m_s.end());
      snaps += sn.size();
      sections += se.size();
    };
    // A block out of order is refused on rank 0 before the others see it; the run goes on.
    EXPECT_THROW(driver.pushLoads(7, sc.loads.data(), 1), std::exception);
    for (size_t f0 = 0; f0 < sc.frames; f0 += 50) {
      const size_t nf = std::min<size_t>(50, sc.frames - f0);
      driver.pushLoads(f0, &sc.loads[f0 * sc.sleeper_x_m.size()], nf);
      driver.advance(driver.model().loadsAvailableUntil());
      take();
    }
    driver.finishLoads();
    driver.finishRun(0.2, 0.02, [&] {  // the loads end at 0.1 s, then hold
      ++slices;
      take();
      return true;
    });
    take();
  }
  EXPECT_NE(partition.find("2 ranks"), std::string::npos) << partition;
  EXPECT_GE(slices, 4u);

  // The same scenario on one rank, driven directly.
  SoilModel one(sc.params, sc.sleeper_x_m, 2000.0);
  std::vector<double> rec_one;
  ReceiverBlock rb;
  std::vector<SurfaceSnapshot> sn;
  std::vector<SectionSnapshot> se;
  one.pushLoads(0, sc.loads.data(), sc.frames);
  one.finishLoads();
  one.finishRun(0.2, 1.0);
  one.takeReceiverSamples(rb);
  one.takeSnapshots(sn);
  one.takeSectionSnapshots(se);
  ASSERT_EQ(rec.size(), rb.velocity_m_s.size());
  EXPECT_EQ(snaps, sn.size());
  EXPECT_EQ(sections, se.size());
  const double peak = maxAbs(rb.velocity_m_s);
  ASSERT_GT(peak, 0.0);
  const double steps = 0.2 / one.dt();
  const double diff = maxAbsDiff(rec, rb.velocity_m_s);
  std::printf("driver on rank 0, %s: %zu receiver values, max |diff| / peak vs 1 rank %.2e (bound %.2e)\n",
              partition.c_str(), rec.size(), diff / peak, steps * std::ldexp(1.0, -24));
  EXPECT_LE(diff, steps * std::ldexp(1.0, -24) * peak);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  g_world = worldSoilComm();
  if (!g_world->root()) {
    // One report: rank 0's (the others run the same collectives and check nothing of their own).
    ::testing::GTEST_FLAG(output) = "";
    delete ::testing::UnitTest::GetInstance()->listeners().Release(
        ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
  }
  const int rc = RUN_ALL_TESTS();
  // Every rank's verdict: a failure on any rank fails the run.
  const double worst = g_world->maximum(rc);
  return worst > 0.0 ? 1 : 0;
}
