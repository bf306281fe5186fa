// railvib/soil: non-reflecting boundaries of the soil box, one unit per method.
//
//   dashpots      Lysmer-Kuhlemeyer viscous boundary on the absorbing faces:
//                 c_n = rho Vp A, c_t = rho Vs A per node (boundary_dashpots.cpp)
//   graded_layer  a mass-proportional damping layer alpha(s) M in front of
//                 the dashpots, alpha = alpha_max (s / L)^n with s the depth
//                 into the layer (boundary_graded_layer.cpp)
//   pml           perfectly matched layer (boundary_pml.cpp), when available
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

struct BoundarySpec {
  BoundaryMethod method = BoundaryMethod::Dashpots;
  GradedLayerSpec graded_layer;
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
