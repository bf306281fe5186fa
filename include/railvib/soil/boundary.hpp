// railvib/soil: non-reflecting boundaries of the soil box, one unit per method.
//
//   dashpots      Lysmer-Kuhlemeyer viscous boundary on the absorbing faces:
//                 c_n = rho Vp A, c_t = rho Vs A per node (boundary_dashpots.cpp)
//   graded_layer  a mass-proportional damping layer alpha(s) M in front of
//                 the dashpots, alpha = alpha_max (s / L)^n with s the depth
//                 into the layer (boundary_graded_layer.cpp)
//   pml           convolutional / multi-axial perfectly matched layer: complex
//                 coordinate stretching s = kappa + d / (alpha + i omega) of the
//                 derivatives, recursive convolution (boundary_pml.cpp)
//
// A boundary acts on the absorbing faces of the mesh (x_min, x_max, y_min,
// y_max, bottom; the top is the free surface). At set-up it may add diagonal
// viscous damping to the nodal update and take elements away from the
// stiffness kernel (it then integrates them itself through a SolverUnit, see
// solver_unit.hpp). To add a method: a BoundaryMethod value, its parameters in
// BoundarySpec and loadBoundarySpec(), a class deriving from SoilBoundary in
// its own file, and a case in makeSoilBoundary(); nothing else changes.
#pragma once

#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver_unit.hpp"

namespace railvib::soil {

/// Faces of the box that absorb outgoing waves (false: a reflecting face, e.g. a symmetry plane).
struct AbsorbingFaces {
  bool x_min = true, x_max = true, y_min = true, y_max = true, bottom = true;
  bool any() const { return x_min || x_max || y_min || y_max || bottom; }
};

enum class BoundaryMethod { Dashpots, GradedLayer, Pml };

std::string boundaryMethodName(BoundaryMethod method);

struct GradedLayerSpec {
  /// Layer thickness (m) along the absorbing faces, and alpha (1/s) at the outer face.
  double thickness_m = 0.0;
  double max_alpha_1_s = 0.0;
  /// Profile exponent n of alpha_max (s / L)^n.
  double exponent = 2.0;
  /// Whether the layer also runs along the bottom (else sides only; the bottom keeps its dashpots).
  bool bottom = true;
};

/// Perfectly matched layer along the absorbing faces (docs/soil.md, "Perfectly matched layer").
/// Per direction l the derivative d/dx_l is stretched by 1 / s_l, s_l = kappa_l + d_l / (alpha_l + i omega)
/// (complex frequency shifted, Kuzuoglu & Mittra 1996; Komatitsch & Martin 2007), with the profile
/// d_l = d0 (s / L)^n, s the distance into the layer, d0 = -(n + 1) c_p ln(R) / (2 L) (Collino & Tsogka 2001),
/// c_p the largest P-wave speed of the mesh; kappa_l = 1 + (kappa_max - 1) (s / L)^n; alpha constant in the layer.
/// Multi-axial (Meza-Fajardo & Papageorgiou 2008): the other two directions get p d_l as well.
struct PmlSpec {
  /// Layer thickness (m) along the absorbing faces; the layer is a whole number of elements, at most this thick.
  double thickness_m = 0.0;
  /// Target reflection coefficient R at normal incidence of a P wave (sets d0); 1 gives d = 0 (tests).
  double reflection_coefficient = 1e-3;
  /// Profile exponent n of (s / L)^n.
  double exponent = 2.0;
  /// kappa at the outer face (1 = no real stretching).
  double max_kappa = 1.0;
  /// CFS frequency shift alpha (1/s), the same throughout the layer: the stretched stiffness keeps
  /// alpha / (kappa alpha + d) of its static value (0 for alpha = 0: static fields would not relax).
  double alpha_1_s = 0.0;
  /// M-PML ratio p: damping p d added in the two directions parallel to the face.
  double perpendicular_ratio = 0.0;
  /// Whether the layer also runs along the bottom (else the bottom keeps plain dashpots).
  bool bottom = true;
  /// Lysmer-Kuhlemeyer dashpots at the outer faces of the layer (else those faces are free).
  bool outer_dashpots = true;
};

struct BoundarySpec {
  BoundaryMethod method = BoundaryMethod::Dashpots;
  GradedLayerSpec graded_layer;
  PmlSpec pml;
};

/// What a boundary needs to know at set-up.
struct BoundaryContext {
  const StructuredMesh* mesh = nullptr;
  const std::vector<double>* mass = nullptr;  // lumped nodal mass (kg)
  AbsorbingFaces faces;
};

class SoilBoundary {
 public:
  virtual ~SoilBoundary() = default;
  virtual BoundaryMethod method() const = 0;
  /// Thickness (m) of the zone along the absorbing faces where the boundary alters the
  /// physics: receivers and loads belong outside it.
  virtual double zoneThicknessM() const { return 0.0; }
  /// Whether that zone also runs along the bottom.
  virtual bool zoneAlongBottom() const { return false; }
  /// Whether loads may act inside that zone (a damping layer: yes, weakly damped; a PML: no, its
  /// fields are not physical there).
  virtual bool zoneTakesLoads() const { return true; }
  /// Elements the stiffness kernel integrates; the boundary's unit integrates the others.
  virtual ElementBox kernelElements(const BoundaryContext& ctx) const { return ElementBox::all(*ctx.mesh); }
  /// Diagonal viscous damping (N s/m) per node and component, added to c[component][node].
  virtual void addNodalDamping(const BoundaryContext& /*ctx*/, std::vector<double> /*c*/[3]) const {}
  /// An upper bound on the explicit step this boundary tolerates (s); infinity when it imposes none.
  virtual double stableStepLimitS(const BoundaryContext& /*ctx*/) const {
    return std::numeric_limits<double>::infinity();
  }
  /// Runtime part for the solver's precision; none by default.
  virtual std::unique_ptr<SolverUnit<float>> makeUnitFloat(const BoundaryContext& /*ctx*/) const { return nullptr; }
  virtual std::unique_ptr<SolverUnit<double>> makeUnitDouble(const BoundaryContext& /*ctx*/) const { return nullptr; }
  /// Method and parameters, for the run summary.
  virtual nlohmann::json summary() const = 0;
};

/// Lysmer-Kuhlemeyer dashpots on the absorbing faces (used by the other methods at their outer face too).
void addLysmerDashpots(const StructuredMesh& mesh, const AbsorbingFaces& faces, std::vector<double> c[3]);

std::unique_ptr<SoilBoundary> makeSoilBoundary(const BoundarySpec& spec);

/// Read `soil.boundary` (method and its parameters). Throws ConfigError.
BoundarySpec loadBoundarySpec(const ConfigNode& boundary);

}  // namespace railvib::soil
