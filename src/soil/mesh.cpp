#include "railvib/soil/mesh.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace railvib::soil {

double Material::vs() const { return std::sqrt(shearModulus() / density_kg_m3); }
double Material::vp() const { return std::sqrt(pModulus() / density_kg_m3); }

double Material::vr() const {
  // Rayleigh equation in x = (c / Vs)^2: (2 - x)^2 - 4 sqrt(1 - x) sqrt(1 - a2 x) = 0, a2 = (Vs/Vp)^2.
  const double a2 = shearModulus() / pModulus();
  auto g = [a2](double x) { return (2.0 - x) * (2.0 - x) - 4.0 * std::sqrt(1.0 - x) * std::sqrt(1.0 - a2 * x); };
  // g < 0 for small x > 0 (g ~ -2 x (1 - a2)), g(1) = 1 > 0: one root in between.
  double lo = 1e-6, hi = 1.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (g(mid) < 0.0) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return vs() * std::sqrt(0.5 * (lo + hi));
}

StructuredMesh buildMesh(const std::vector<Layer>& profile, const MeshSpec& spec) {
  if (profile.empty()) throw std::invalid_argument("soil mesh: empty layer profile");
  if (!(spec.x_max_m > spec.x_min_m) || !(spec.y_max_m > spec.y_min_m) || !(spec.depth_m > 0.0)) {
    throw std::invalid_argument("soil mesh: empty box");
  }
  if (!(spec.f_max_hz > 0.0) || !(spec.elements_per_wavelength > 0.0)) {
    throw std::invalid_argument("soil mesh: f_max and elements_per_wavelength must be positive");
  }
  StructuredMesh mesh;
  const double ratio = spec.f_max_hz * spec.elements_per_wavelength;
  // In-plane size: the softest layer present within the depth.
  double h_plane = 1e300;
  double top = 0.0;
  for (size_t l = 0; l < profile.size(); ++l) {
    const bool half_space = (l + 1 == profile.size());
    if (!half_space && !(profile[l].thickness_m > 0.0)) throw std::invalid_argument("soil mesh: layer thickness <= 0");
    if (top >= spec.depth_m) break;
    h_plane = std::min(h_plane, profile[l].material.vs() / ratio);
    if (!half_space) top += profile[l].thickness_m;
  }
  if (spec.max_plane_size_m > 0.0) h_plane = std::min(h_plane, spec.max_plane_size_m);
  const double lx = spec.x_max_m - spec.x_min_m, ly = spec.y_max_m - spec.y_min_m;
  // Count the elements in floating point before any index or array is sized: a box or a
  // resolution far beyond any machine is refused here, not by running out of memory.
  {
    double levels = 0.0, top_m = 0.0;
    for (size_t l = 0; l < profile.size() && top_m < spec.depth_m - 1e-12; ++l) {
      const bool half_space = (l + 1 == profile.size());
      const double bottom = half_space ? spec.depth_m : std::min(spec.depth_m, top_m + profile[l].thickness_m);
      levels += std::max(1.0, std::ceil((bottom - top_m) / (profile[l].material.vs() / ratio)));
      top_m = bottom;
    }
    const double elements = std::ceil(lx / h_plane) * std::ceil(ly / h_plane) * levels;
    if (!(elements <= kMaxMeshElements)) {
      std::ostringstream why;
      why << "soil mesh: " << elements << " elements, more than the " << kMaxMeshElements
          << " any machine could hold, whatever max_memory_gb allows: lower f_max_hz / elements_per_wavelength or "
             "shrink the box";
      throw std::invalid_argument(why.str());
    }
  }
  mesh.nx = static_cast<size_t>(std::ceil(lx / h_plane - 1e-9));
  mesh.ny = static_cast<size_t>(std::ceil(ly / h_plane - 1e-9));
  mesh.hx = lx / static_cast<double>(mesh.nx);
  mesh.hy = ly / static_cast<double>(mesh.ny);
  mesh.x0 = spec.x_min_m;
  mesh.y0 = spec.y_min_m;
  mesh.z.push_back(0.0);
  top = 0.0;
  for (size_t l = 0; l < profile.size() && top < spec.depth_m - 1e-12; ++l) {
    const bool half_space = (l + 1 == profile.size());
    const double bottom = half_space ? spec.depth_m : std::min(spec.depth_m, top + profile[l].thickness_m);
    const double t = bottom - top;
    const double h = profile[l].material.vs() / ratio;
    const size_t n = std::max<size_t>(1, static_cast<size_t>(std::ceil(t / h - 1e-9)));
    const double dz = t / static_cast<double>(n);
    mesh.materials.push_back(profile[l].material);
    for (size_t q = 1; q <= n; ++q) {
      mesh.z.push_back(q == n ? bottom : top + dz * static_cast<double>(q));
      mesh.level_material.push_back(mesh.materials.size() - 1);
    }
    LayerMeshInfo info;
    info.top_m = top;
    info.bottom_m = bottom;
    info.levels = n;
    info.dz_m = dz;
    info.material = profile[l].material;
    info.resolved_hz = profile[l].material.vs() / (spec.elements_per_wavelength * std::max({mesh.hx, mesh.hy, dz}));
    mesh.layers.push_back(info);
    top = bottom;
  }
  mesh.nz = mesh.level_material.size();
  addInclusions(mesh, spec.inclusions, spec.inclusion_snap_tolerance_m);
  return mesh;
}

const Material* StructuredMesh::elementMaterial(size_t i, size_t j, size_t k) const {
  for (const MeshInclusion& inc : inclusions) {
    if (inc.elements.contains(i, j, k)) return inc.is_void ? nullptr : &inc.material;
  }
  return &levelMaterial(k);
}

namespace {
// The node plane nearest to `value` among planes[0..count] (uniform: origin + h q; else the list).
struct Snapped {
  size_t index;
  double moved_m;
};
Snapped snapUniform(double value, double origin, double h, size_t count) {
  const double s = std::round((value - origin) / h);
  const size_t q = s <= 0.0 ? 0 : std::min(count, static_cast<size_t>(s));
  return {q, std::abs(origin + h * static_cast<double>(q) - value)};
}
Snapped snapPlanes(double value, const std::vector<double>& planes) {
  size_t best = 0;
  for (size_t q = 1; q < planes.size(); ++q) {
    if (std::abs(planes[q] - value) < std::abs(planes[best] - value)) best = q;
  }
  return {best, std::abs(planes[best] - value)};
}
}  // namespace

MeshInclusion snapInclusion(const StructuredMesh& mesh, const InclusionSpec& spec, double tolerance_m) {
  const std::string who = "soil inclusion '" + spec.name + "'";
  const char* axis[3] = {"x", "y", "depth"};
  const double lo_m[3] = {spec.x_min_m, spec.y_min_m, spec.top_m};
  const double hi_m[3] = {spec.x_max_m, spec.y_max_m, spec.bottom_m};
  const double mesh_lo[3] = {mesh.x0, mesh.y0, 0.0};
  const double mesh_hi[3] = {mesh.xMax(), mesh.yMax(), mesh.depth()};
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(lo_m[a]) || !std::isfinite(hi_m[a])) {
      throw InclusionError(who + ": a face along " + axis[a] + " is not a finite number", axis[a]);
    }
    if (!(hi_m[a] > lo_m[a])) {
      throw InclusionError(who + ": an empty box along " + axis[a] + " (the far face must lie beyond the near one)",
                           axis[a]);
    }
    // Faces on the mesh's own faces count as inside whatever the round-off of the node planes.
    const double slack = 1e-9 * (1.0 + std::abs(mesh_lo[a]) + std::abs(mesh_hi[a]));
    if (lo_m[a] < mesh_lo[a] - slack || hi_m[a] > mesh_hi[a] + slack) {
      std::ostringstream why;
      why << who << " spans " << axis[a] << " [" << lo_m[a] << ", " << hi_m[a] << "] m, not inside the soil mesh's ["
          << mesh_lo[a] << ", " << mesh_hi[a] << "] m"
          << (a == 2 ? " (deeper than the mesh, or above the surface)" : "");
      throw InclusionError(why.str(), axis[a]);
    }
  }
  const Snapped s[6] = {snapUniform(spec.x_min_m, mesh.x0, mesh.hx, mesh.nx),
                        snapUniform(spec.x_max_m, mesh.x0, mesh.hx, mesh.nx),
                        snapUniform(spec.y_min_m, mesh.y0, mesh.hy, mesh.ny),
                        snapUniform(spec.y_max_m, mesh.y0, mesh.hy, mesh.ny),
                        snapPlanes(spec.top_m, mesh.z),
                        snapPlanes(spec.bottom_m, mesh.z)};
  MeshInclusion inc;
  inc.name = spec.name;
  inc.is_void = spec.is_void;
  inc.material = spec.material;
  inc.rayleigh_beta_s = spec.rayleigh_beta_s;
  inc.implicit = spec.implicit;
  inc.elements = {s[0].index, s[1].index, s[2].index, s[3].index, s[4].index, s[5].index};
  // A box thinner than one element along an axis would vanish from the mesh or be inflated by the snapping.
  double element[3] = {mesh.hx, mesh.hy, 1e300};
  for (size_t k = 0; k < mesh.nz; ++k) {
    if (mesh.z[k + 1] > spec.top_m && mesh.z[k] < spec.bottom_m)
      element[2] = std::min(element[2], mesh.z[k + 1] - mesh.z[k]);
  }
  const size_t lo[3] = {inc.elements.i0, inc.elements.j0, inc.elements.k0};
  const size_t hi[3] = {inc.elements.i1, inc.elements.j1, inc.elements.k1};
  for (int a = 0; a < 3; ++a) {
    const double extent = hi_m[a] - lo_m[a];
    if (hi[a] <= lo[a] || extent < element[a] * (1.0 - 1e-9)) {
      std::ostringstream why;
      why << who << " is " << extent << " m thick along " << axis[a] << ", thinner than one element there ("
          << element[a] << " m): refine the mesh (soil.mesh.f_max_hz, elements_per_wavelength, max_plane_size_m) "
          << "or thicken the box";
      throw InclusionError(why.str(), axis[a]);
    }
    const double moved = std::max(s[2 * a].moved_m, s[2 * a + 1].moved_m);
    inc.moved_m = std::max(inc.moved_m, moved);
    if (moved > tolerance_m) {
      std::ostringstream why;
      why << who << ": snapping it to the element faces would move a face along " << axis[a] << " by " << moved
          << " m, more than the tolerance " << tolerance_m << " m (element size there " << element[a]
          << " m): refine the mesh, move the box onto element faces or raise the tolerance";
      throw InclusionError(why.str(), axis[a]);
    }
  }
  return inc;
}

void addInclusions(StructuredMesh& mesh, const std::vector<InclusionSpec>& specs, double tolerance_m) {
  for (const InclusionSpec& spec : specs) {
    MeshInclusion inc = snapInclusion(mesh, spec, tolerance_m);
    for (const MeshInclusion& other : mesh.inclusions) {
      if (!inc.elements.intersect(other.elements).empty()) {
        throw InclusionError("soil inclusions '" + other.name + "' and '" + inc.name +
                                 "' overlap (as snapped to the mesh): inclusions must be disjoint",
                             "");
      }
    }
    mesh.inclusions.push_back(std::move(inc));
  }
}

StructuredMesh buildUniformMesh(size_t nx, size_t ny, double hx, double hy, const std::vector<double>& z_planes,
                                const std::vector<Material>& level_materials, double x0, double y0) {
  if (z_planes.size() != level_materials.size() + 1 || nx == 0 || ny == 0 || level_materials.empty()) {
    throw std::invalid_argument("buildUniformMesh: inconsistent sizes");
  }
  StructuredMesh mesh;
  mesh.nx = nx;
  mesh.ny = ny;
  mesh.nz = level_materials.size();
  mesh.hx = hx;
  mesh.hy = hy;
  mesh.x0 = x0;
  mesh.y0 = y0;
  mesh.z = z_planes;
  for (size_t k = 0; k < level_materials.size(); ++k) {
    mesh.materials.push_back(level_materials[k]);
    mesh.level_material.push_back(k);
    LayerMeshInfo info;
    info.top_m = z_planes[k];
    info.bottom_m = z_planes[k + 1];
    info.levels = 1;
    info.dz_m = z_planes[k + 1] - z_planes[k];
    info.material = level_materials[k];
    mesh.layers.push_back(info);
  }
  return mesh;
}

std::array<double, 576> boxElementStiffness(double hx, double hy, double hz, double lambda, double mu) {
  std::array<double, 576> k{};
  const double g = 1.0 / std::sqrt(3.0);
  const double h[3] = {hx, hy, hz};
  const double det = hx * hy * hz / 8.0;
  Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) d(i, j) = lambda;
    d(i, i) = lambda + 2.0 * mu;
    d(i + 3, i + 3) = mu;
  }
  for (int gp = 0; gp < 8; ++gp) {
    const double xi[3] = {(gp & 1) ? g : -g, (gp & 2) ? g : -g, (gp & 4) ? g : -g};
    Eigen::Matrix<double, 6, 24> b = Eigen::Matrix<double, 6, 24>::Zero();
    for (int c = 0; c < 8; ++c) {
      const double s[3] = {(c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0};
      double dn[3];
      for (int a = 0; a < 3; ++a) {
        double v = s[a] / 8.0 * 2.0 / h[a];
        for (int o = 0; o < 3; ++o) {
          if (o != a) v *= (1.0 + s[o] * xi[o]);
        }
        dn[a] = v;
      }
      // strains: xx, yy, zz, yz, xz, xy (engineering shear)
      b(0, 3 * c + 0) = dn[0];
      b(1, 3 * c + 1) = dn[1];
      b(2, 3 * c + 2) = dn[2];
      b(3, 3 * c + 1) = dn[2];
      b(3, 3 * c + 2) = dn[1];
      b(4, 3 * c + 0) = dn[2];
      b(4, 3 * c + 2) = dn[0];
      b(5, 3 * c + 0) = dn[1];
      b(5, 3 * c + 1) = dn[0];
    }
    const Eigen::Matrix<double, 24, 24> ke = b.transpose() * d * b * det;
    for (int r = 0; r < 24; ++r) {
      for (int q = 0; q < 24; ++q) k[static_cast<size_t>(r * 24 + q)] += ke(r, q);
    }
  }
  return k;
}

double boxElementMaxEigenvalue(double hx, double hy, double hz, const Material& m) {
  const auto k = boxElementStiffness(hx, hy, hz, m.lambda(), m.shearModulus());
  Eigen::Matrix<double, 24, 24> km;
  for (int r = 0; r < 24; ++r) {
    for (int q = 0; q < 24; ++q) km(r, q) = k[static_cast<size_t>(r * 24 + q)];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 24, 24>> es(km, Eigen::EigenvaluesOnly);
  const double lumped = m.density_kg_m3 * hx * hy * hz / 8.0;
  return es.eigenvalues().maxCoeff() / lumped;
}

}  // namespace railvib::soil
