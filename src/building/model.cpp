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

// The structured mesh of the house, built in the order walls, interior walls, slabs (node and
// element numbering follow that order).
class MeshBuilder {
 public:
  explicit MeshBuilder(const BuildingParams& p) : p_(p) {
    const double h = p.element_size_m;
    mesh_.element_size_m = h;
    mesh_.x0_m = 0.5 * p.wall_thickness_m;
    mesh_.x1_m = p.length_m - 0.5 * p.wall_thickness_m;
    mesh_.y0_m = 0.5 * p.wall_thickness_m;
    mesh_.y1_m = p.width_m - 0.5 * p.wall_thickness_m;
    mesh_.sections = {{"masonry_walls", "masonry", shellOf(p.wall, p.wall_thickness_m)},
                      {"concrete_floors", "concrete_floors", shellOf(p.floor, p.floor_thickness_m)},
                      {"foundation_walls", "concrete_foundation", shellOf(p.foundation, p.foundation_wall_thickness_m)},
                      {"base_slab", "concrete_foundation", shellOf(p.foundation, p.base_slab_thickness_m)}};
    nx_ = divisions(mesh_.x1_m - mesh_.x0_m, h);
    ny_ = divisions(mesh_.y1_m - mesh_.y0_m, h);
    xs_.resize(nx_ + 1);
    ys_.resize(ny_ + 1);
    for (int i = 0; i <= nx_; ++i) xs_[i] = mesh_.x0_m + (mesh_.x1_m - mesh_.x0_m) * i / nx_;
    for (int j = 0; j <= ny_; ++j) ys_[j] = mesh_.y0_m + (mesh_.y1_m - mesh_.y0_m) * j / ny_;
    buildLevels();
  }

  BuildingMesh build() {
    addExteriorWalls();
    addInteriorWalls();
    addSlabs();
    return std::move(mesh_);
  }

 private:
  struct Level {
    double z;
    std::string group;  // empty: no slab
    int section;
    double support_t;  // thickness of the walls bounding the slab (clear interior)
  };

  // Slab levels (base slab, ground floor, upper floors, top) and the vertical node planes between them.
  void buildLevels() {
    levels_.push_back({-p_.foundation_depth_m, "base_slab", kBaseSlab, p_.foundation_wall_thickness_m});
    levels_.push_back({0.0, "slab_0", kFloor, p_.foundation_wall_thickness_m});
    const double sh = p_.height_m / p_.storeys;
    for (int k = 1; k < p_.storeys; ++k)
      levels_.push_back({k * sh, "slab_" + std::to_string(k), kFloor, p_.wall_thickness_m});
    levels_.push_back({p_.height_m, p_.roof_slab ? "roof" : "", kFloor, p_.wall_thickness_m});
    for (size_t l = 0; l < levels_.size(); ++l) {
      if (l == 0) {
        zs_.push_back(levels_[0].z);
      } else {
        const double z0 = levels_[l - 1].z;
        const double z1 = levels_[l].z;
        const int n = divisions(z1 - z0, p_.element_size_m);
        for (int s = 1; s <= n; ++s) zs_.push_back(s == n ? z1 : z0 + (z1 - z0) * s / n);
      }
      level_k_.push_back(static_cast<int>(zs_.size()) - 1);
    }
  }

  int node(int i, int j, int k) {
    auto key = std::make_tuple(i, j, k);
    auto it = ids_.find(key);
    if (it != ids_.end()) return it->second;
    const int id = static_cast<int>(mesh_.nodes.size());
    mesh_.nodes.emplace_back(xs_[i], ys_[j], zs_[k]);
    ids_.emplace(key, id);
    return id;
  }

  int group(const std::string& name) {
    auto it = std::find(mesh_.groups.begin(), mesh_.groups.end(), name);
    if (it != mesh_.groups.end()) return static_cast<int>(it - mesh_.groups.begin());
    mesh_.groups.push_back(name);
    return static_cast<int>(mesh_.groups.size()) - 1;
  }

  bool inOpening(const std::string& wall, double s, double z) const {
    for (const Opening& o : p_.openings) {
      if (o.wall == wall && s > o.start_m && s < o.start_m + o.width_m && z > o.bottom_m && z < o.bottom_m + o.height_m)
        return true;
    }
    return false;
  }

  // The corner nodes are created in the order given (a braced list is evaluated left to right).
  void addQuad(const std::array<int, 4>& corners, int section, int g, double mass_scale = 1.0) {
    mesh_.elements.push_back({corners, section, g, mass_scale});
  }

  // A vertical element from (i0, j0) to (i1, j1) between node planes k and k + 1.
  void addVerticalQuad(int i0, int j0, int i1, int j1, int k, int section, int g) {
    addQuad({node(i0, j0, k), node(i1, j1, k), node(i1, j1, k + 1), node(i0, j0, k + 1)}, section, g);
  }

  // One element of an exterior wall (of the foundation box below ground), unless in an opening.
  void addWallElement(const std::string& wall, bool below, double s, double zc, int i0, int j0, int i1, int j1, int k) {
    if (!below && inOpening(wall, s, zc)) return;
    addVerticalQuad(i0, j0, i1, j1, k, below ? kFoundationWall : kMasonry,
                    group(below ? "foundation_walls" : "wall_" + wall));
  }

  void addExteriorWalls() {
    for (size_t k = 0; k + 1 < zs_.size(); ++k) {
      const bool below = zs_[k + 1] <= 1e-9;
      const double zc = 0.5 * (zs_[k] + zs_[k + 1]);
      const int kk = static_cast<int>(k);
      for (int i = 0; i < nx_; ++i) {
        const double xc = 0.5 * (xs_[i] + xs_[i + 1]);
        addWallElement("front", below, xc, zc, i, 0, i + 1, 0, kk);
        addWallElement("back", below, xc, zc, i, ny_, i + 1, ny_, kk);
      }
      for (int j = 0; j < ny_; ++j) {
        const double yc = 0.5 * (ys_[j] + ys_[j + 1]);
        addWallElement("left", below, yc, zc, 0, j, 0, j + 1, kk);
        addWallElement("right", below, yc, zc, nx_, j, nx_, j + 1, kk);
      }
    }
  }

  // Interior walls: masonry, from the ground slab to the top of the walls, on the nearest mesh line.
  // (Their crossing with the slabs is counted twice in the mass: t_wall x t_slab per metre, documented.)
  void addInteriorWalls() {
    const int k_ground = level_k_[1];
    const int k_top = static_cast<int>(zs_.size()) - 1;
    for (const InteriorWall& w : p_.interior_walls) {
      const int g = group(w.along == "x" ? "wall_interior_x" : "wall_interior_y");
      if (w.along == "x") {
        const int j = static_cast<int>(std::lround((w.position_m - mesh_.y0_m) / (mesh_.y1_m - mesh_.y0_m) * ny_));
        if (j <= 0 || j >= ny_) continue;
        for (int k = k_ground; k < k_top; ++k)
          for (int i = 0; i < nx_; ++i) addVerticalQuad(i, j, i + 1, j, k, kMasonry, g);
      } else {
        const int i = static_cast<int>(std::lround((w.position_m - mesh_.x0_m) / (mesh_.x1_m - mesh_.x0_m) * nx_));
        if (i <= 0 || i >= nx_) continue;
        for (int k = k_ground; k < k_top; ++k)
          for (int j = 0; j < ny_; ++j) addVerticalQuad(i, j, i, j + 1, k, kMasonry, g);
      }
    }
  }

  // Slabs (mass only over the clear interior between the walls' faces).
  void addSlabs() {
    for (size_t l = 0; l < levels_.size(); ++l) {
      if (levels_[l].group.empty()) continue;
      const int g = group(levels_[l].group);
      if (levels_[l].z > 1e-9 || std::abs(levels_[l].z) <= 1e-9) mesh_.slab_levels_m.push_back(levels_[l].z);
      const double ht = 0.5 * levels_[l].support_t;
      const int k = level_k_[l];
      for (int i = 0; i < nx_; ++i) {
        for (int j = 0; j < ny_; ++j) {
          const double area = (xs_[i + 1] - xs_[i]) * (ys_[j + 1] - ys_[j]);
          const double clear = overlap(xs_[i], xs_[i + 1], mesh_.x0_m + ht, mesh_.x1_m - ht) *
                               overlap(ys_[j], ys_[j + 1], mesh_.y0_m + ht, mesh_.y1_m - ht);
          addQuad({node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k)}, levels_[l].section, g,
                  clear / area);
        }
      }
    }
  }

  const BuildingParams& p_;
  BuildingMesh mesh_;
  int nx_ = 0, ny_ = 0;
  std::vector<double> xs_, ys_, zs_;
  std::vector<Level> levels_;
  std::vector<int> level_k_;
  std::map<std::tuple<int, int, int>, int> ids_;
};

}  // namespace

BuildingMesh buildMesh(const BuildingParams& p) { return MeshBuilder(p).build(); }

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
                     at.origin_y_m + 0.5 * at.width_m * row, 0.0, ""});
    }
  }
  if (!p.response_points.empty()) {
    const NamedPoint& r = p.response_points.front();
    out.push_back({names::kBuildingResponseFreeFieldPoint, at.trackX(r.x_m), at.trackY(r.y_m), 0.0, ""});
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
    os << "config error: " << (pt.key.empty() ? std::string("building.response_points") : pt.key) << ": point '"
       << pt.name << "' at (" << pt.x_m << ", " << pt.y_m << ", " << pt.z_m
       << ") m (building frame) is not on a wall or a slab of the model: nearest node " << dist << " m away (allowed "
       << allowed << " m)";
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
