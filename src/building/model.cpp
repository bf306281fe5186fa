#include "railvib/building/model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "railvib/common/config.hpp"
#include "railvib/common/names.hpp"

namespace railvib::building {
namespace {

int divisions(double length, double h) { return std::max(1, static_cast<int>(std::lround(length / h))); }

enum Section { kMasonry = 0, kFloor = 1, kFoundationWall = 2, kBaseSlab = 3 };

ShellSection shellOf(const ShellMaterial& m, double t) {
  ShellSection s;
  s.young_modulus_pa = m.young_modulus_pa;
  s.poisson = m.poisson();
  s.thickness_m = t;
  s.density_kg_m3 = m.density_kg_m3;
  return s;
}

double overlap(double a0, double a1, double b0, double b1) {
  return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}

}  // namespace

BuildingMesh buildMesh(const BuildingParams& p) {
  BuildingMesh mesh;
  const double h = p.element_size_m;
  mesh.element_size_m = h;
  mesh.x0_m = 0.5 * p.wall_thickness_m;
  mesh.x1_m = p.length_m - 0.5 * p.wall_thickness_m;
  mesh.y0_m = 0.5 * p.wall_thickness_m;
  mesh.y1_m = p.width_m - 0.5 * p.wall_thickness_m;
  mesh.sections = {{"masonry_walls", "masonry", shellOf(p.wall, p.wall_thickness_m)},
                   {"concrete_floors", "concrete_floors", shellOf(p.floor, p.floor_thickness_m)},
                   {"foundation_walls", "concrete_foundation", shellOf(p.foundation, p.foundation_wall_thickness_m)},
                   {"base_slab", "concrete_foundation", shellOf(p.foundation, p.base_slab_thickness_m)}};

  const int nx = divisions(mesh.x1_m - mesh.x0_m, h);
  const int ny = divisions(mesh.y1_m - mesh.y0_m, h);
  std::vector<double> xs(nx + 1), ys(ny + 1);
  for (int i = 0; i <= nx; ++i) xs[i] = mesh.x0_m + (mesh.x1_m - mesh.x0_m) * i / nx;
  for (int j = 0; j <= ny; ++j) ys[j] = mesh.y0_m + (mesh.y1_m - mesh.y0_m) * j / ny;

  // Levels and the vertical grid.
  struct Level {
    double z;
    std::string group;  // empty: no slab
    int section;
    double support_t;  // thickness of the walls bounding the slab (clear interior)
  };
  std::vector<Level> levels;
  levels.push_back({-p.foundation_depth_m, "base_slab", kBaseSlab, p.foundation_wall_thickness_m});
  levels.push_back({0.0, "slab_0", kFloor, p.foundation_wall_thickness_m});
  const double sh = p.height_m / p.storeys;
  for (int k = 1; k < p.storeys; ++k)
    levels.push_back({k * sh, "slab_" + std::to_string(k), kFloor, p.wall_thickness_m});
  levels.push_back({p.height_m, p.roof_slab ? "roof" : "", kFloor, p.wall_thickness_m});
  std::vector<double> zs;
  std::vector<int> level_k;
  for (size_t l = 0; l < levels.size(); ++l) {
    if (l == 0) {
      zs.push_back(levels[0].z);
    } else {
      const double z0 = levels[l - 1].z;
      const double z1 = levels[l].z;
      const int n = divisions(z1 - z0, h);
      for (int s = 1; s <= n; ++s) zs.push_back(s == n ? z1 : z0 + (z1 - z0) * s / n);
    }
    level_k.push_back(static_cast<int>(zs.size()) - 1);
  }

  std::map<std::tuple<int, int, int>, int> ids;
  auto node = [&](int i, int j, int k) {
    auto key = std::make_tuple(i, j, k);
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const int id = static_cast<int>(mesh.nodes.size());
    mesh.nodes.emplace_back(xs[i], ys[j], zs[k]);
    ids.emplace(key, id);
    return id;
  };
  auto group = [&](const std::string& name) {
    auto it = std::find(mesh.groups.begin(), mesh.groups.end(), name);
    if (it != mesh.groups.end()) return static_cast<int>(it - mesh.groups.begin());
    mesh.groups.push_back(name);
    return static_cast<int>(mesh.groups.size()) - 1;
  };
  auto inOpening = [&](const std::string& wall, double s, double z) {
    for (const Opening& o : p.openings) {
      if (o.wall == wall && s > o.start_m && s < o.start_m + o.width_m && z > o.bottom_m && z < o.bottom_m + o.height_m)
        return true;
    }
    return false;
  };

  // Walls.
  for (size_t k = 0; k + 1 < zs.size(); ++k) {
    const bool below = zs[k + 1] <= 1e-9;
    const int sec = below ? kFoundationWall : kMasonry;
    const double zc = 0.5 * (zs[k] + zs[k + 1]);
    const int kk = static_cast<int>(k);
    for (int i = 0; i < nx; ++i) {
      const double xc = 0.5 * (xs[i] + xs[i + 1]);
      if (below || !inOpening("front", xc, zc))
        mesh.elements.push_back({{node(i, 0, kk), node(i + 1, 0, kk), node(i + 1, 0, kk + 1), node(i, 0, kk + 1)},
                                 sec,
                                 group(below ? "foundation_walls" : "wall_front"),
                                 1.0});
      if (below || !inOpening("back", xc, zc))
        mesh.elements.push_back({{node(i, ny, kk), node(i + 1, ny, kk), node(i + 1, ny, kk + 1), node(i, ny, kk + 1)},
                                 sec,
                                 group(below ? "foundation_walls" : "wall_back"),
                                 1.0});
    }
    for (int j = 0; j < ny; ++j) {
      const double yc = 0.5 * (ys[j] + ys[j + 1]);
      if (below || !inOpening("left", yc, zc))
        mesh.elements.push_back({{node(0, j, kk), node(0, j + 1, kk), node(0, j + 1, kk + 1), node(0, j, kk + 1)},
                                 sec,
                                 group(below ? "foundation_walls" : "wall_left"),
                                 1.0});
      if (below || !inOpening("right", yc, zc))
        mesh.elements.push_back({{node(nx, j, kk), node(nx, j + 1, kk), node(nx, j + 1, kk + 1), node(nx, j, kk + 1)},
                                 sec,
                                 group(below ? "foundation_walls" : "wall_right"),
                                 1.0});
    }
  }
  // Interior walls: masonry, from the ground slab to the top of the walls, on the nearest mesh line.
  // (Their crossing with the slabs is counted twice in the mass: t_wall x t_slab per metre, documented.)
  const int k_ground = level_k[1];
  for (const InteriorWall& w : p.interior_walls) {
    const int g = group(w.along == "x" ? "wall_interior_x" : "wall_interior_y");
    if (w.along == "x") {
      const int j = static_cast<int>(std::lround((w.position_m - mesh.y0_m) / (mesh.y1_m - mesh.y0_m) * ny));
      if (j <= 0 || j >= ny) continue;
      for (int k = k_ground; k + 1 < static_cast<int>(zs.size()); ++k)
        for (int i = 0; i < nx; ++i)
          mesh.elements.push_back(
              {{node(i, j, k), node(i + 1, j, k), node(i + 1, j, k + 1), node(i, j, k + 1)}, kMasonry, g, 1.0});
    } else {
      const int i = static_cast<int>(std::lround((w.position_m - mesh.x0_m) / (mesh.x1_m - mesh.x0_m) * nx));
      if (i <= 0 || i >= nx) continue;
      for (int k = k_ground; k + 1 < static_cast<int>(zs.size()); ++k)
        for (int j = 0; j < ny; ++j)
          mesh.elements.push_back(
              {{node(i, j, k), node(i, j + 1, k), node(i, j + 1, k + 1), node(i, j, k + 1)}, kMasonry, g, 1.0});
    }
  }
  // Slabs (mass only over the clear interior between the walls' faces).
  for (size_t l = 0; l < levels.size(); ++l) {
    if (levels[l].group.empty()) continue;
    const int g = group(levels[l].group);
    if (levels[l].z > 1e-9 || std::abs(levels[l].z) <= 1e-9) mesh.slab_levels_m.push_back(levels[l].z);
    const double ht = 0.5 * levels[l].support_t;
    const int k = level_k[l];
    for (int i = 0; i < nx; ++i) {
      for (int j = 0; j < ny; ++j) {
        const double area = (xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]);
        const double clear = overlap(xs[i], xs[i + 1], mesh.x0_m + ht, mesh.x1_m - ht) *
                             overlap(ys[j], ys[j + 1], mesh.y0_m + ht, mesh.y1_m - ht);
        mesh.elements.push_back({{node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k)},
                                 levels[l].section,
                                 g,
                                 clear / area});
      }
    }
  }
  return mesh;
}

double handComputedMass(const BuildingParams& p) {
  const double lm = p.length_m - p.wall_thickness_m;  // mid-line rectangle
  const double wm = p.width_m - p.wall_thickness_m;
  const double perimeter = 2.0 * (lm + wm);
  const double rho_c = p.foundation.density_kg_m3;
  double mass = p.wall.density_kg_m3 * p.wall_thickness_m * perimeter * p.height_m;  // masonry ring
  mass += rho_c * p.foundation_wall_thickness_m * perimeter * p.foundation_depth_m;  // foundation walls
  const double tf = p.foundation_wall_thickness_m;
  mass += rho_c * p.base_slab_thickness_m * (lm - tf) * (wm - tf);              // base slab
  mass += p.floor.density_kg_m3 * p.floor_thickness_m * (lm - tf) * (wm - tf);  // ground slab
  const int upper = (p.storeys - 1) + (p.roof_slab ? 1 : 0);
  mass += upper * p.floor.density_kg_m3 * p.floor_thickness_m * (lm - p.wall_thickness_m) * (wm - p.wall_thickness_m);
  return mass;
}

std::vector<FootprintPoint> footprintPoints(const BuildingParams& p) {
  const double x0 = 0.5 * p.wall_thickness_m, x1 = p.length_m - 0.5 * p.wall_thickness_m;
  const double y0 = 0.5 * p.wall_thickness_m, y1 = p.width_m - 0.5 * p.wall_thickness_m;
  std::vector<FootprintPoint> out;
  for (int j = 0; j < p.footprint_ny; ++j) {
    for (int i = 0; i < p.footprint_nx; ++i) {
      FootprintPoint f;
      f.name = names::footprintPoint(i, j);
      f.x_building_m = x0 + (x1 - x0) * i / (p.footprint_nx - 1);
      f.y_building_m = y0 + (y1 - y0) * j / (p.footprint_ny - 1);
      f.x_track_m = p.placement.trackX(f.x_building_m);
      f.y_track_m = p.placement.trackY(f.y_building_m);
      f.z_track_m = 0.0;
      out.push_back(f);
    }
  }
  return out;
}

std::vector<NamedPoint> freeFieldPoints(const BuildingParams& p) {
  const BuildingPlacement& at = p.placement;
  std::vector<NamedPoint> out;
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      out.push_back({names::buildingPlanPoint(row, column), at.origin_x_m + 0.5 * at.length_m * column,
                     at.origin_y_m + 0.5 * at.width_m * row, 0.0});
    }
  }
  if (!p.response_points.empty()) {
    const NamedPoint& r = p.response_points.front();
    out.push_back({names::kBuildingResponseFreeFieldPoint, at.trackX(r.x_m), at.trackY(r.y_m), 0.0});
  }
  return out;
}

BuildingModel::BuildingModel(const BuildingParams& params) : params_(params), mesh_(buildMesh(params)) {
  const int ndof = dofCount();
  m_ = Eigen::VectorXd::Zero(ndof);
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(mesh_.elements.size() * 576);
  for (const MeshElement& e : mesh_.elements) {
    ShellNodes x;
    for (int a = 0; a < 4; ++a) x[a] = mesh_.nodes[e.nodes[a]];
    const ShellSection& sec = mesh_.sections[e.section].shell;
    const ShellMatrix ke = shellStiffness(x, sec);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int r = 0; r < 6; ++r)
          for (int c = 0; c < 6; ++c)
            trip.emplace_back(e.nodes[a] * 6 + r, e.nodes[b] * 6 + c, ke(6 * a + r, 6 * b + c));
    const auto areas = shellNodalAreas(x);
    for (int a = 0; a < 4; ++a) {
      const double m = sec.density_kg_m3 * sec.thickness_m * areas[a] * e.mass_scale;
      for (int d = 0; d < 3; ++d) m_[e.nodes[a] * 6 + d] += m;
    }
  }
  k_.resize(ndof, ndof);
  k_.setFromTriplets(trip.begin(), trip.end());

  // Foundation nodes: the box below the ground surface, the wall feet at the
  // ground surface, and the ground slab if it rests on the fill.
  const double eps = 1e-9;
  foundation_node_.assign(mesh_.nodes.size(), false);
  for (size_t n = 0; n < mesh_.nodes.size(); ++n) {
    const Eigen::Vector3d& x = mesh_.nodes[n];
    const bool perimeter = std::abs(x.x() - mesh_.x0_m) < eps || std::abs(x.x() - mesh_.x1_m) < eps ||
                           std::abs(x.y() - mesh_.y0_m) < eps || std::abs(x.y() - mesh_.y1_m) < eps;
    foundation_node_[n] = x.z() < -eps || (std::abs(x.z()) <= eps && (perimeter || params_.ground_slab_on_fill));
  }
  free_index_.assign(ndof, -1);
  for (int d = 0; d < ndof; ++d) {
    if (foundation_node_[d / 6]) {
      constrained_dofs_.push_back(d);
    } else {
      free_index_[d] = static_cast<int>(free_dofs_.size());
      free_dofs_.push_back(d);
    }
  }

  // Mirror maps (the structured mesh is symmetric about both mid-planes unless openings break it).
  const double xm = mesh_.x0_m + mesh_.x1_m, ym = mesh_.y0_m + mesh_.y1_m;
  const double tol = 1e-6 * std::max(params_.length_m, params_.width_m);
  auto quantise = [tol](const Eigen::Vector3d& v) {
    return std::make_tuple(std::lround(v.x() / tol), std::lround(v.y() / tol), std::lround(v.z() / tol));
  };
  std::map<std::tuple<long, long, long>, int> lookup;
  for (size_t n = 0; n < mesh_.nodes.size(); ++n) lookup[quantise(mesh_.nodes[n])] = static_cast<int>(n);
  for (int axis = 0; axis < 2; ++axis) {
    mirror_[axis].assign(mesh_.nodes.size(), -1);
    for (size_t n = 0; n < mesh_.nodes.size(); ++n) {
      Eigen::Vector3d v = mesh_.nodes[n];
      if (axis == 0)
        v.x() = xm - v.x();
      else
        v.y() = ym - v.y();
      auto it = lookup.find(quantise(v));
      if (it != lookup.end()) mirror_[axis][n] = it->second;
    }
  }

  for (const NamedPoint& pt : params_.response_points) response_nodes_.push_back(snap(pt));
}

double BuildingModel::totalMass() const {
  double s = 0.0;
  for (int n = 0; n < static_cast<int>(mesh_.nodes.size()); ++n) s += m_[n * 6 + 2];
  return s;
}

ResponseNode BuildingModel::snap(const NamedPoint& pt) const {
  const Eigen::Vector3d q(pt.x_m, pt.y_m, pt.z_m);
  std::vector<bool> used(mesh_.nodes.size(), false);
  for (const MeshElement& e : mesh_.elements)
    for (int a : e.nodes) used[a] = true;
  int best = -1;
  double dist = 1e300;
  for (size_t n = 0; n < mesh_.nodes.size(); ++n) {
    if (!used[n]) continue;
    const double d = (mesh_.nodes[n] - q).norm();
    if (d < dist) {
      dist = d;
      best = static_cast<int>(n);
    }
  }
  // A point is on the structure if it is within one element of a node (slab or wall surface, or the wall faces).
  const double allowed =
      mesh_.element_size_m * 0.75 + 0.5 * std::max(params_.wall_thickness_m, params_.floor_thickness_m);
  if (best < 0 || dist > allowed) {
    std::ostringstream os;
    os << "config error: building.response_points: point '" << pt.name << "' at (" << pt.x_m << ", " << pt.y_m << ", "
       << pt.z_m << ") m (building frame) is not on a wall or a slab of the model: nearest node " << dist
       << " m away (allowed " << allowed << " m)";
    throw ConfigError(os.str());
  }
  ResponseNode r;
  r.name = pt.name;
  r.node = best;
  r.requested = q;
  r.position = mesh_.nodes[best];
  return r;
}

}  // namespace railvib::building
