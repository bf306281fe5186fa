// railvib/soil: structured hexahedral mesh of a layered soil box.
//
// Internal frame: x along the track, y lateral, d = depth (down from the free
// surface, d = 0). The mesh is a box [x0, x0 + nx hx] x [y0, y0 + ny hy] x
// [0, depth]: uniform in x and y, graded in depth, with every layer interface
// on an element face. Node (i, j, k) has index i + (nx + 1) * (j + (ny + 1) * k),
// k = 0 at the surface. Element level k lies between node planes k and k + 1
// and carries one material.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace railvib::soil {

/// Isotropic linear elastic material.
struct Material {
  double young_modulus_pa = 0.0;
  double density_kg_m3 = 0.0;
  double poisson_ratio = 0.0;

  double shearModulus() const { return young_modulus_pa / (2.0 * (1.0 + poisson_ratio)); }
  double lambda() const {
    return young_modulus_pa * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
  /// Constrained (P-wave) modulus lambda + 2 G.
  double pModulus() const { return lambda() + 2.0 * shearModulus(); }
  double vs() const;
  double vp() const;
  /// Rayleigh wave speed (root of the Rayleigh equation).
  double vr() const;
};

/// One layer of the profile; the last entry of a profile is the half-space
/// (its thickness is ignored: the mesh stops at the requested depth).
struct Layer {
  double thickness_m = 0.0;
  Material material;
};

struct StructuredMesh;

/// A box of elements [i0, i1) x [j0, j1) x [k0, k1) of a StructuredMesh (levels k
/// counted down from the surface), e.g. the elements a stiffness kernel integrates.
struct ElementBox {
  size_t i0 = 0, i1 = 0, j0 = 0, j1 = 0, k0 = 0, k1 = 0;

  static ElementBox all(const StructuredMesh& m);
  bool empty() const { return i1 <= i0 || j1 <= j0 || k1 <= k0; }
  size_t count() const { return empty() ? 0 : (i1 - i0) * (j1 - j0) * (k1 - k0); }
  bool contains(size_t i, size_t j, size_t k) const {
    return i >= i0 && i < i1 && j >= j0 && j < j1 && k >= k0 && k < k1;
  }
  bool operator==(const ElementBox& o) const {
    return i0 == o.i0 && i1 == o.i1 && j0 == o.j0 && j1 == o.j1 && k0 == o.k0 && k1 == o.k1;
  }
  /// The common part of two boxes (empty if they do not overlap).
  ElementBox intersect(const ElementBox& o) const {
    auto mx = [](size_t a, size_t b) { return a > b ? a : b; };
    auto mn = [](size_t a, size_t b) { return a < b ? a : b; };
    return {mx(i0, o.i0), mn(i1, o.i1), mx(j0, o.j0), mn(j1, o.j1), mx(k0, o.k0), mn(k1, o.k1)};
  }
};

/// A box of the soil with a material of its own (a stiff wall, a soft trench fill, a concrete
/// foundation) or with none (a void: an open trench, a cut-out, whose faces are free surfaces), in
/// the mesh's frame: x along the track, y lateral, depth down from the surface. buildMesh snaps its
/// faces to the nearest element faces (snapInclusion).
struct InclusionSpec {
  std::string name;
  bool is_void = false;
  /// The box's material (ignored for a void).
  Material material;
  /// Its stiffness-proportional Rayleigh coefficient (s); < 0: the soil's (SolverOptions::rayleigh_beta_s).
  double rayleigh_beta_s = -1.0;
  /// Integrate its stiffness implicitly (soil/implicit_unit.hpp): a stiff material then does not set the
  /// explicit step. Such an inclusion is undamped (rayleigh_beta_s 0).
  bool implicit = false;
  double x_min_m = 0.0, x_max_m = 0.0, y_min_m = 0.0, y_max_m = 0.0;
  double top_m = 0.0, bottom_m = 0.0;  // depth of the top and bottom faces
};

/// An inclusion as meshed: its elements and by how much snapping moved its faces.
struct MeshInclusion {
  std::string name;
  ElementBox elements;
  bool is_void = false;
  Material material;
  double rayleigh_beta_s = -1.0;
  bool implicit = false;
  /// Largest distance (m) a face moved to the nearest element face.
  double moved_m = 0.0;
};

/// What sets the element sizes.
struct MeshSpec {
  double x_min_m = -10.0, x_max_m = 10.0;
  double y_min_m = -10.0, y_max_m = 10.0;
  double depth_m = 10.0;
  double f_max_hz = 60.0;
  /// Elements per shear wavelength Vs / f_max in each layer.
  double elements_per_wavelength = 8.0;
  /// Cap on the in-plane element size (0 = none), e.g. to resolve a load footprint.
  double max_plane_size_m = 0.0;
  /// Material inclusions and voids (none by default); they may not overlap.
  std::vector<InclusionSpec> inclusions;
  /// Largest distance (m) snapping may move an inclusion's face.
  double inclusion_snap_tolerance_m = 0.25;
};

/// Summary of one element level band (a layer as meshed).
struct LayerMeshInfo {
  double top_m = 0.0, bottom_m = 0.0;
  size_t levels = 0;
  double dz_m = 0.0;
  /// Highest frequency with elements_per_wavelength elements per shear
  /// wavelength, using the largest element dimension of the level.
  double resolved_hz = 0.0;
  Material material;
};

/// buildMesh refuses meshes with more elements (a 10^10-element mesh needs ~1 TB).
constexpr double kMaxMeshElements = 1.0e10;

struct StructuredMesh {
  size_t nx = 0, ny = 0, nz = 0;
  double x0 = 0.0, y0 = 0.0, hx = 0.0, hy = 0.0;
  std::vector<double> z;               // node plane depths, size nz + 1, z[0] = 0
  std::vector<size_t> level_material;  // per element level, index into materials
  std::vector<Material> materials;
  std::vector<LayerMeshInfo> layers;  // one per meshed layer (half-space last)
  /// Element boxes whose material is not their level's (MeshSpec::inclusions, snapped); disjoint.
  std::vector<MeshInclusion> inclusions;

  size_t nodeCount() const { return (nx + 1) * (ny + 1) * (nz + 1); }
  size_t elementCount() const { return nx * ny * nz; }
  size_t node(size_t i, size_t j, size_t k) const { return i + (nx + 1) * (j + (ny + 1) * k); }
  double x(size_t i) const { return x0 + hx * static_cast<double>(i); }
  double y(size_t j) const { return y0 + hy * static_cast<double>(j); }
  double xMax() const { return x(nx); }
  double yMax() const { return y(ny); }
  double depth() const { return z.back(); }
  const Material& levelMaterial(size_t k) const { return materials[level_material[k]]; }
  /// The material of element (i, j, k): an inclusion's, else its level's; nullptr in a void.
  const Material* elementMaterial(size_t i, size_t j, size_t k) const;
};

inline ElementBox ElementBox::all(const StructuredMesh& m) { return {0, m.nx, 0, m.ny, 0, m.nz}; }

/// Build the graded mesh. Throws std::invalid_argument on an impossible spec
/// (non-positive sizes, layers thinner than zero, ...).
StructuredMesh buildMesh(const std::vector<Layer>& profile, const MeshSpec& spec);

/// A refused inclusion, with the axis of its box at fault: "x", "y", "depth", or "" (the box as a whole).
class InclusionError : public std::invalid_argument {
 public:
  InclusionError(const std::string& what, std::string axis) : std::invalid_argument(what), axis_(std::move(axis)) {}
  const std::string& axis() const { return axis_; }

 private:
  std::string axis_;
};

/// Snap an inclusion to the element faces of `mesh`: each face to the nearest node plane. Throws
/// InclusionError (naming the inclusion) when it is not inside the mesh, is thinner than one
/// element along an axis, or a face would move by more than `tolerance_m`.
MeshInclusion snapInclusion(const StructuredMesh& mesh, const InclusionSpec& spec, double tolerance_m);
/// Snap the inclusions and add them to the mesh (buildMesh does this with MeshSpec::inclusions).
/// Throws InclusionError as snapInclusion, or (axis "") when two inclusions share an element.
void addInclusions(StructuredMesh& mesh, const std::vector<InclusionSpec>& specs, double tolerance_m);

/// Build a mesh from explicit node planes (tests): uniform hx, hy; z planes given.
StructuredMesh buildUniformMesh(size_t nx, size_t ny, double hx, double hy, const std::vector<double>& z_planes,
                                const std::vector<Material>& level_materials, double x0 = 0.0, double y0 = 0.0);

/// 24 x 24 stiffness of a box hexahedron (trilinear, 2x2x2 Gauss, exact for a
/// box), row-major, dof = corner * 3 + component, corner = a + 2 b + 4 c for
/// the node at (a hx, b hy, c hz).
std::array<double, 576> boxElementStiffness(double hx, double hy, double hz, double lambda, double mu);

/// Largest eigenvalue of M_e^-1 K_e for a box element with lumped mass (an
/// upper bound of the assembled lambda_max(M^-1 K), Irons' element bound).
double boxElementMaxEigenvalue(double hx, double hy, double hz, const Material& m);

}  // namespace railvib::soil
