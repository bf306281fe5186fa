// Material inclusions and voids in the soil mesh (MeshSpec::inclusions, src/soil/inclusion_unit.hpp).
//
// The checks are equivalences that hold exactly in the finite element model, so they are asserted to
// round-off (double precision, 300-600 steps: 1e-9 of the peak where the operation order differs,
// bitwise where it cannot):
//  - an inclusion of its surrounding layer's own material changes nothing (bitwise: the difference
//    stiffness it adds is exactly zero);
//  - an inclusion over whole element levels with another material is the mesh whose levels have that
//    material, and with a Rayleigh coefficient of its own it is the soil with that coefficient;
//  - a void is free surface: a void over the bottom levels is the shallower mesh with a free bottom,
//    a void over the last element columns is the shorter mesh with a free end face (the traction-free
//    condition is the natural boundary condition of the weak form: the cut faces of the truncated mesh
//    are free by construction).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/solver.hpp"
#include "soil_test_util.hpp"

using namespace railvib::soil;
using railvib::soil::testing::kConcrete;
using railvib::soil::testing::maxAbs;

namespace {

const Material kLayer1{61.0e6, 1876.0, 0.13}, kLayer2{84.0e6, 1876.0, 0.13}, kHalfSpace{465.0e6, 1992.0, 0.3};

// 12 x 10 elements of 0.25 m, 12 levels: 4 of layer 1, 4 of layer 2, 4 of half-space.
StructuredMesh smallMesh(size_t nx = 12, size_t nz = 12) {
  std::vector<double> z{0.0};
  std::vector<Material> mats;
  for (size_t k = 0; k < nz; ++k) {
    z.push_back(z.back() + (k < 4 ? 0.2 : 0.3));
    mats.push_back(k < 4 ? kLayer1 : (k < 8 ? kLayer2 : kHalfSpace));
  }
  return buildUniformMesh(nx, 10, 0.25, 0.25, z, mats, -1.5, -1.25);
}

SolverOptions freeBoxOptions(Precision precision, KernelKind kernel, double dt_s) {
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};  // every face free: a void may reach any of them
  o.kernel = kernel;
  o.precision = precision;
  o.threads = 1;
  o.rayleigh_beta_s = 4.0e-4;
  o.dt_s = dt_s;
  return o;
}

InclusionSpec box(const std::string& name, double x0, double x1, double y0, double y1, double top, double bottom) {
  InclusionSpec s;
  s.name = name;
  s.x_min_m = x0, s.x_max_m = x1, s.y_min_m = y0, s.y_max_m = y1, s.top_m = top, s.bottom_m = bottom;
  return s;
}

// A vertical Hann pulse on a surface patch, then free vibration; every node's displacement, 3 components,
// and the surface v_d every step, on the nodes (i, j, k) with i <= max_i and k <= max_k.
struct History {
  std::vector<double> values;
};
History runPulse(Solver& s, int steps, size_t max_i, size_t max_k) {
  const StructuredMesh& m = s.mesh();
  ForceChannel ch;
  for (size_t j = 3; j <= 5; ++j) {
    for (size_t i = 3; i <= 5; ++i) {
      ch.nodes.push_back(m.node(i, j, 0));
      ch.components.push_back(2);
      ch.weights.push_back(1.0 / 9.0);
    }
  }
  s.addForceChannel(ch);
  History h;
  for (int n = 0; n < steps; ++n) {
    const double t = s.time();
    s.setChannelValues({t < 0.01 ? 1.0e4 * (0.5 - 0.5 * std::cos(2.0 * M_PI * t / 0.01)) : 0.0});
    s.step();
    for (size_t k = 0; k <= max_k; ++k) {
      for (size_t j = 0; j <= m.ny; ++j) {
        for (size_t i = 0; i <= max_i; ++i) {
          for (int c = 0; c < 3; ++c) h.values.push_back(s.displacement(m.node(i, j, k), c));
        }
      }
    }
  }
  return h;
}

double relativeDifference(const History& a, const History& b) {
  return railvib::soil::testing::maxAbsDiff(a.values, b.values) / maxAbs(b.values);
}

constexpr double kDt = 2.0e-5;  // below every mesh's limit here (concrete 0.25 m: 4.9e-5 s)

}  // namespace

TEST(SoilInclusion, SnapsToElementFacesAndSaysHowFar) {
  const StructuredMesh m = smallMesh();
  // x [-0.9, 0.1] -> node planes 2.4 -> 2 and 6.4 -> 6 (moved 0.1 m); depth [0.15, 1.0]: planes 0.2 and 1.1.
  const MeshInclusion inc = snapInclusion(m, box("wall", -0.9, 0.1, -0.5, 0.5, 0.15, 1.0), 0.25);
  EXPECT_EQ(inc.elements, (ElementBox{2, 6, 3, 7, 1, 5}));
  EXPECT_NEAR(inc.moved_m, 0.1, 1e-12);
  // Thinner than one element (0.25 m) along y, even if rounding would keep one element.
  EXPECT_THROW(snapInclusion(m, box("thin", -0.9, 0.1, -0.5, -0.3, 0.0, 1.0), 0.25), std::invalid_argument);
  EXPECT_THROW(snapInclusion(m, box("thin", -0.9, 0.1, -0.5, -0.45, 0.0, 1.0), 0.25), std::invalid_argument);
  // A face moved by more than the tolerance.
  EXPECT_THROW(snapInclusion(m, box("far", -0.9, 0.1, -0.5, 0.5, 0.15, 1.0), 0.05), std::invalid_argument);
  // Deeper than the mesh (3.2 m), outside it, an empty box.
  EXPECT_THROW(snapInclusion(m, box("deep", -0.9, 0.1, -0.5, 0.5, 0.0, 3.5), 0.25), std::invalid_argument);
  EXPECT_THROW(snapInclusion(m, box("out", -2.0, 0.1, -0.5, 0.5, 0.0, 1.0), 0.25), std::invalid_argument);
  EXPECT_THROW(snapInclusion(m, box("empty", 0.1, -0.9, -0.5, 0.5, 0.0, 1.0), 0.25), std::invalid_argument);
  InclusionSpec nan = box("nan", -0.9, 0.1, -0.5, 0.5, 0.0, 1.0);
  nan.x_max_m = std::nan("");
  EXPECT_THROW(snapInclusion(m, nan, 0.25), std::invalid_argument);
  // Two boxes sharing an element.
  StructuredMesh two = smallMesh();
  EXPECT_THROW(
      addInclusions(two, {box("a", -1.0, 0.0, -0.5, 0.5, 0.0, 1.0), box("b", -0.5, 0.5, 0.0, 1.0, 0.6, 1.6)}, 0.25),
      std::invalid_argument);
  // The element materials follow: level, inclusion, void.
  StructuredMesh three = smallMesh();
  InclusionSpec wall = box("wall", -1.0, 0.0, -0.5, 0.5, 0.0, 0.4);
  wall.material = kConcrete;
  InclusionSpec trench = box("trench", 0.5, 1.0, -0.5, 0.5, 0.0, 0.4);
  trench.is_void = true;
  addInclusions(three, {wall, trench}, 0.25);
  EXPECT_EQ(three.elementMaterial(0, 0, 0)->young_modulus_pa, kLayer1.young_modulus_pa);
  EXPECT_EQ(three.elementMaterial(2, 3, 0)->young_modulus_pa, kConcrete.young_modulus_pa);
  EXPECT_EQ(three.elementMaterial(8, 3, 1), nullptr);
  EXPECT_EQ(three.elementMaterial(8, 3, 2)->young_modulus_pa, kLayer1.young_modulus_pa);
}

TEST(SoilInclusion, HostMaterialReproducesTheRunWithoutIt) {
  for (KernelKind kernel : {KernelKind::Element, KernelKind::Stencil}) {
    for (Precision pr : {Precision::Float, Precision::Double}) {
      StructuredMesh with = smallMesh();
      InclusionSpec same = box("same", -1.0, 0.5, -0.75, 0.5, 0.0, 0.8);  // levels 0-3: layer 1
      same.material = kLayer1;
      addInclusions(with, {same}, 0.25);
      Solver a(smallMesh(), freeBoxOptions(pr, kernel, 0.0));
      Solver b(with, freeBoxOptions(pr, kernel, 0.0));
      EXPECT_EQ(a.dt(), b.dt());
      const History ha = runPulse(a, 300, 12, 12), hb = runPulse(b, 300, 12, 12);
      ASSERT_GT(maxAbs(ha.values), 0.0);
      EXPECT_EQ(ha.values, hb.values) << kernelName(kernel);  // bitwise: it adds exactly zero
    }
  }
}

TEST(SoilInclusion, WholeLevelsOfAnotherMaterialEqualTheLayeredMesh) {
  // Concrete over levels 4-7 (the second layer), everywhere in plane.
  std::vector<double> z{0.0};
  std::vector<Material> mats;
  for (size_t k = 0; k < 12; ++k) {
    z.push_back(z.back() + (k < 4 ? 0.2 : 0.3));
    mats.push_back(k < 4 ? kLayer1 : (k < 8 ? kConcrete : kHalfSpace));
  }
  const StructuredMesh layered = buildUniformMesh(12, 10, 0.25, 0.25, z, mats, -1.5, -1.25);
  StructuredMesh with = smallMesh();
  InclusionSpec slab = box("slab", -1.5, 1.5, -1.25, 1.25, 0.8, 2.0);
  slab.material = kConcrete;
  addInclusions(with, {slab}, 0.25);
  for (KernelKind kernel : {KernelKind::Element, KernelKind::Stencil}) {
    Solver a(layered, freeBoxOptions(Precision::Double, kernel, 0.0));
    Solver b(with, freeBoxOptions(Precision::Double, kernel, 0.0));
    // The stable step follows the stiff material (and the mass): the same limit in both.
    EXPECT_NEAR(b.dtUndamped(), a.dtUndamped(), 1e-12 * a.dtUndamped());
    EXPECT_EQ(b.nodalMass(b.mesh().node(4, 4, 6)), a.nodalMass(a.mesh().node(4, 4, 6)));
    const double d = relativeDifference(runPulse(b, 600, 12, 12), runPulse(a, 600, 12, 12));
    std::printf("concrete levels as an inclusion vs as layers (%s): max |diff| / peak = %.2e\n",
                kernelName(kernel).c_str(), d);
    EXPECT_LT(d, 1e-9) << kernelName(kernel);
  }
}

TEST(SoilInclusion, OwnRayleighCoefficientEqualsTheSoilWithIt) {
  // The whole box as an inclusion of the soil's own materials (one per layer) with beta 1.2e-3 s instead of
  // the soil's 4e-4 s: the soil with beta 1.2e-3 s (the filtered velocity vf is the same; K (u + beta_i vf)).
  StructuredMesh with = smallMesh();
  const Material mats[3] = {kLayer1, kLayer2, kHalfSpace};
  for (int l = 0; l < 3; ++l) {
    InclusionSpec layer = box("layer" + std::to_string(l), -1.5, 1.5, -1.25, 1.25, l == 0 ? 0.0 : 0.8 + 1.2 * (l - 1),
                              l == 0 ? 0.8 : 0.8 + 1.2 * l);
    layer.material = mats[l];
    layer.rayleigh_beta_s = 1.2e-3;
    with.inclusions.push_back(snapInclusion(with, layer, 1e-9));
  }
  SolverOptions damped = freeBoxOptions(Precision::Double, KernelKind::Stencil, 0.0);
  damped.rayleigh_beta_s = 1.2e-3;
  Solver a(smallMesh(), damped);
  Solver b(with, freeBoxOptions(Precision::Double, KernelKind::Stencil, 0.0));
  EXPECT_NEAR(b.dtDamped(), a.dtDamped(), 1e-12 * a.dtDamped());
  const History ha = runPulse(a, 600, 12, 12), hb = runPulse(b, 600, 12, 12);
  const double d = relativeDifference(hb, ha);
  std::printf("own Rayleigh coefficient vs the soil's: max |diff| / peak = %.2e\n", d);
  EXPECT_LT(d, 1e-9);
  // And it is not the soil's 4e-4 s.
  Solver c(smallMesh(), freeBoxOptions(Precision::Double, KernelKind::Stencil, a.dt()));
  EXPECT_GT(relativeDifference(runPulse(c, 600, 12, 12), ha), 1e-3);
}

TEST(SoilInclusion, VoidBelowIsTheShallowerMeshWithAFreeBottom) {
  // Void over levels 8-11 (depth 2.0-3.2 m) everywhere in plane: the 8-level mesh, whose bottom is free.
  StructuredMesh with = smallMesh();
  InclusionSpec cut = box("cut", -1.5, 1.5, -1.25, 1.25, 2.0, 3.2);
  cut.is_void = true;
  addInclusions(with, {cut}, 0.25);
  for (KernelKind kernel : {KernelKind::Element, KernelKind::Stencil}) {
    Solver a(smallMesh(12, 8), freeBoxOptions(Precision::Double, kernel, kDt));
    Solver b(with, freeBoxOptions(Precision::Double, kernel, kDt));
    // The void's inner nodes carry no mass; its face nodes half the elements' (their soil side).
    EXPECT_EQ(b.nodalMass(b.mesh().node(5, 5, 10)), 0.0);
    EXPECT_EQ(b.nodalMass(b.mesh().node(5, 5, 8)), a.nodalMass(a.mesh().node(5, 5, 8)));
    const double d = relativeDifference(runPulse(b, 600, 12, 8), runPulse(a, 600, 12, 8));
    std::printf("void below vs the shallower mesh (%s): max |diff| / peak = %.2e\n", kernelName(kernel).c_str(), d);
    EXPECT_LT(d, 1e-9) << kernelName(kernel);
    EXPECT_EQ(b.displacement(b.mesh().node(5, 5, 10), 2), 0.0);  // held still
  }
}

TEST(SoilInclusion, VoidAtTheEndIsTheShorterMeshWithAFreeFace) {
  // Void over element columns 8-11, all depths: the 8-column mesh with a free face at x = 0.5 m.
  StructuredMesh with = smallMesh();
  InclusionSpec cut = box("cut", 0.5, 1.5, -1.25, 1.25, 0.0, 3.2);
  cut.is_void = true;
  addInclusions(with, {cut}, 0.25);
  for (KernelKind kernel : {KernelKind::Element, KernelKind::Stencil}) {
    Solver a(smallMesh(8, 12), freeBoxOptions(Precision::Double, kernel, kDt));
    Solver b(with, freeBoxOptions(Precision::Double, kernel, kDt));
    // Both histories list nodes (i <= 8, j, k) in the same order, each by its own mesh's numbering.
    const History ha = runPulse(a, 400, 8, 12);
    const History hb = runPulse(b, 400, 8, 12);
    const double d = relativeDifference(hb, ha);
    std::printf("void at the end vs the shorter mesh (%s): max |diff| / peak = %.2e\n", kernelName(kernel).c_str(), d);
    EXPECT_LT(d, 1e-9) << kernelName(kernel);
  }
}

TEST(SoilInclusion, StiffInclusionSetsTheStableStep) {
  StructuredMesh with = smallMesh();
  InclusionSpec wall = box("wall", -1.0, 0.0, -0.5, 0.5, 0.0, 0.8);
  wall.material = kConcrete;
  addInclusions(with, {wall}, 0.25);
  SolverOptions o = freeBoxOptions(Precision::Float, KernelKind::Stencil, 0.0);
  const Solver plain(smallMesh(), o), stiff(with, o);
  const double expected = 2.0 / std::sqrt(boxElementMaxEigenvalue(0.25, 0.25, 0.2, kConcrete));
  EXPECT_NEAR(stiff.dtUndamped(), expected, 1e-12 * expected);
  EXPECT_LT(stiff.dtUndamped(), 0.5 * plain.dtUndamped());
  // A load on a node inside a void is refused.
  StructuredMesh holed = smallMesh();
  InclusionSpec pit = box("pit", -1.0, 0.0, -0.5, 0.5, 0.0, 0.8);
  pit.is_void = true;
  addInclusions(holed, {pit}, 0.25);
  Solver s(holed, o);
  ForceChannel ch{{s.mesh().node(3, 4, 2)}, {2}, {1.0}};
  EXPECT_THROW(s.addForceChannel(ch), std::invalid_argument);
  // A rigid body over the void is refused.
  RigidBodySpec body;
  body.x_min_m = -0.75, body.x_max_m = 0.25, body.y_min_m = -0.25, body.y_max_m = 0.25;
  EXPECT_THROW(s.attachRigidBody(body), std::invalid_argument);
}

TEST(SoilInclusion, RefusedInTheBoundaryZone) {
  SolverOptions o;
  o.threads = 1;
  o.boundary.method = BoundaryMethod::Pml;
  o.boundary.pml.thickness_m = 0.5;  // 2 elements
  StructuredMesh m = smallMesh();
  addInclusions(m, {box("into_pml", -1.25, 0.0, -0.5, 0.5, 0.0, 0.8)}, 0.25);
  m.inclusions.back().material = kConcrete;
  EXPECT_THROW(Solver(m, o), std::invalid_argument);
  StructuredMesh ok = smallMesh();
  addInclusions(ok, {box("inside", -1.0, 0.0, -0.5, 0.5, 0.0, 0.8)}, 0.25);
  ok.inclusions.back().material = kConcrete;
  EXPECT_NO_THROW(Solver(ok, o));
  // Dashpots: an inclusion may not touch an absorbing face.
  o.boundary.method = BoundaryMethod::Dashpots;
  StructuredMesh edge = smallMesh();
  addInclusions(edge, {box("edge", -1.5, 0.0, -0.5, 0.5, 0.0, 0.8)}, 0.25);
  EXPECT_THROW(Solver(edge, o), std::invalid_argument);
}

namespace {
// The small scenario of the soil tests with `inclusions` under soil.
railvib::Config scenarioWith(const std::string& inclusions,
                             const std::string& sensors = "[{name: s2, x_m: 0.0, y_m: 2.0}]") {
  std::string text = railvib::soil::testing::smallScenario(
      "{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, poisson_ratio: 0.13}", "", sensors);
  const std::string anchor = "  rayleigh_beta_s: 4.0e-4\n";
  text.replace(text.find(anchor), anchor.size(), anchor + "  inclusions:\n" + inclusions);
  return railvib::Config::fromString(text);
}
std::string refusal(const railvib::Config& c) {
  try {
    loadSoilParams(c.root());
  } catch (const railvib::ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SoilInclusion, ConfigReadsAndRefusesWithTheKey) {
  const std::string trench =
      "    - {name: trench, kind: void, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [0.0, 1.0]}\n";
  const std::string wall =
      "    - {name: wall, kind: material, x_m: [-2.0, 2.0], y_m: [-3.3, -2.5], depth_m: [0.0, 2.5],\n"
      "       material: {young_modulus_pa: 20.0e9, density_kg_m3: 2400.0, poisson_ratio: 0.2}}\n";
  const SoilParams p = loadSoilParams(scenarioWith(trench + wall).root());
  ASSERT_EQ(p.mesh.inclusions.size(), 2u);
  EXPECT_TRUE(p.mesh.inclusions[0].is_void);
  EXPECT_EQ(p.mesh.inclusions[1].material.young_modulus_pa, 20.0e9);
  EXPECT_LT(p.mesh.inclusions[1].rayleigh_beta_s, 0.0);  // the soil's
  const StructuredMesh m = buildMesh(p.profile, p.mesh);
  ASSERT_EQ(m.inclusions.size(), 2u);
  EXPECT_LE(m.inclusions[0].moved_m, 0.25);

  struct Bad {
    std::string yaml, key, why;
  };
  const std::vector<Bad> bad = {
      {"    - {name: t, kind: void, x_m: [-2.0, 2.0], y_m: [-0.4, 0.4], depth_m: [0.0, 1.0]}\n",
       "soil.inclusions[0].y_m", "through the track"},
      {"    - {name: t, kind: void, x_m: [-2.0, 2.0], y_m: [1.6, 2.4], depth_m: [0.0, 1.0]}\n",
       "soil.inclusions[0].y_m", "holds receiver 's2'"},
      {"    - {name: t, kind: void, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [0.0, 9.0]}\n",
       "soil.inclusions[0].depth_m", "deeper than the mesh"},
      {"    - {name: t, kind: void, x_m: [-2.0, 2.0], y_m: [2.6, 2.7], depth_m: [0.0, 1.0]}\n",
       "soil.inclusions[0].y_m", "thinner than one element"},
      {"    - {name: t, kind: hole, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [0.0, 1.0]}\n",
       "soil.inclusions[0].kind", "hole"},
      {"    - {name: t, kind: material, integration: sideways, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [0.0, "
       "1.0],\n"
       "       material: {young_modulus_pa: 20.0e9, density_kg_m3: 2400.0, poisson_ratio: 0.2}}\n",
       "soil.inclusions[0].integration", "sideways"},
      {"    - {name: t, kind: material, integration: implicit, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [0.0, "
       "1.0],\n"
       "       material: {young_modulus_pa: 20.0e9, density_kg_m3: 2400.0, poisson_ratio: 0.2, rayleigh_beta_s: "
       "-1.0e-4}}\n",
       "soil.inclusions[0].material.rayleigh_beta_s", "out of range"},
      {"    - {name: t, kind: void, x_m: [2.0, -2.0], y_m: [2.6, 3.4], depth_m: [0.0, 1.0]}\n",
       "soil.inclusions[0].x_m", "must exceed the first"},
      {"    - {name: t, kind: void, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [-1.0, 1.0]}\n",
       "soil.inclusions[0].depth_m", "out of range"},
      {"    - {name: t, kind: material, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [0.0, 1.0],\n"
       "       material: {young_modulus_pa: -1.0, density_kg_m3: 2400.0, poisson_ratio: 0.2}}\n",
       "soil.inclusions[0].material.young_modulus_pa", "out of range"},
      {trench + "    - {name: trench, kind: void, x_m: [-2.0, 2.0], y_m: [-3.4, -2.6], depth_m: [0.0, 1.0]}\n",
       "soil.inclusions[1].name", "names two inclusions"},
      {trench + "    - {name: t2, kind: void, x_m: [-1.0, 1.0], y_m: [2.6, 3.4], depth_m: [0.5, 2.5]}\n",
       "soil.inclusions[1].name", "overlap"},
      {"    - {name: t, kind: void, x_m: [-2.0, 2.0], y_m: [2.6, 3.4], depth_m: [0.0, 4.0]}\n",
       "soil.inclusions[0].depth_m", "absorbing boundary"},
  };
  for (const Bad& b : bad) {
    const std::string what = refusal(scenarioWith(b.yaml));
    EXPECT_NE(what.find(b.key), std::string::npos) << b.yaml << " -> " << what;
    EXPECT_NE(what.find(b.why), std::string::npos) << b.yaml << " -> " << what;
  }
}
