// railvib/building: shell finite element model of the house.
//
// Idealisation (docs/building.md): every wall and slab is a shell on its
// mid-surface. Walls run on the mid-lines of the outer plan, i.e. on a
// rectangle (length - t) x (width - t). Levels (z, building frame):
//   -depth          base slab of the embedded concrete box foundation
//   [-depth, 0]     concrete foundation walls (the sides of the box)
//   0               ground floor slab (top of the box)
//   k height/storeys   upper floors (k = 1 .. storeys-1)
//   height          top of the masonry walls (roof slab only if roof_slab)
// Masses follow the solid: walls on their mid-line ring (exact), slabs only
// over the clear interior between the walls' faces.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <array>
#include <string>
#include <vector>

#include "railvib/building/params.hpp"
#include "railvib/building/shell.hpp"

namespace railvib::building {

constexpr int kDofPerNode = 6;

struct MeshElement {
  std::array<int, 4> nodes;
  int section = 0;          ///< index into BuildingMesh::sections
  int group = 0;            ///< index into BuildingMesh::groups
  double mass_scale = 1.0;  ///< fraction of the element area that carries its own material
};

struct SectionInfo {
  std::string name;      ///< e.g. "masonry_walls"
  std::string material;  ///< e.g. "masonry"
  ShellSection shell;
};

struct BuildingMesh {
  std::vector<Eigen::Vector3d> nodes;  ///< building frame (m)
  std::vector<MeshElement> elements;
  std::vector<SectionInfo> sections;
  std::vector<std::string>
      groups;  ///< wall_front/back/left/right, wall_interior_x/y, foundation_walls, base_slab, slab_k, roof
  std::vector<double> slab_levels_m;                      ///< z of slabs above the foundation base (ground floor first)
  double x0_m = 0.0, x1_m = 0.0, y0_m = 0.0, y1_m = 0.0;  ///< wall mid-line rectangle
  double element_size_m = 0.0;
};

/// Structured mesh of the house from its parameters.
BuildingMesh buildMesh(const BuildingParams& params);

/// Hand computation of the mass of walls, floors and foundation (kg), from the
/// solid's dimensions (no mesh): the reference for the model's mass.
double handComputedMass(const BuildingParams& params);

/// A point where the soil must output velocities: name and position in the track frame.
struct FootprintPoint {
  std::string name;
  double x_track_m = 0.0;
  double y_track_m = 0.0;
  double z_track_m = 0.0;
  double x_building_m = 0.0;
  double y_building_m = 0.0;
};

/// Footprint receivers (a regular nx x ny grid on the foundation's wall mid-line
/// rectangle, at the ground surface), in the order used by every streaming API.
std::vector<FootprintPoint> footprintPoints(const BuildingParams& params);

/// Free-field soil receivers of the house plan, frame track, on the surface (where the house
/// stands, without it): its corners, wall mid-points and centre (names::buildingPlanPoint), and
/// the plan position of the first response point (names::kBuildingResponseFreeFieldPoint), to
/// compare the house's response with the ground's.
std::vector<NamedPoint> freeFieldPoints(const BuildingParams& params);

/// A response point snapped to the nearest mesh node.
struct ResponseNode {
  std::string name;
  int node = -1;
  Eigen::Vector3d requested;  ///< building frame
  Eigen::Vector3d position;   ///< node position, building frame
};

/// Assembled model: global K, lumped M, and the partition into free DOFs and
/// DOFs constrained to the foundation (nodes of the foundation box).
class BuildingModel {
 public:
  explicit BuildingModel(const BuildingParams& params);

  const BuildingParams& params() const { return params_; }
  const BuildingMesh& mesh() const { return mesh_; }
  int dofCount() const { return static_cast<int>(mesh_.nodes.size()) * kDofPerNode; }
  const Eigen::SparseMatrix<double>& stiffness() const { return k_; }
  /// Lumped mass (diagonal; zero on rotations).
  const Eigen::VectorXd& mass() const { return m_; }
  double totalMass() const;

  /// Nodes that follow the soil (fixed in the fixed-base analysis).
  const std::vector<bool>& foundationNode() const { return foundation_node_; }
  /// Free DOF index of each global DOF (-1 if constrained).
  const std::vector<int>& freeIndex() const { return free_index_; }
  const std::vector<int>& freeDofs() const { return free_dofs_; }
  const std::vector<int>& constrainedDofs() const { return constrained_dofs_; }

  const std::vector<ResponseNode>& responseNodes() const { return response_nodes_; }
  /// Snap a point (building frame) to a node; throws ConfigError-like std::invalid_argument if off the structure.
  ResponseNode snap(const NamedPoint& point) const;

  /// Node of the mirror image of each node about x = mid (axis 0) or y = mid (axis 1); -1 if none.
  const std::vector<int>& mirror(int axis) const { return mirror_[axis]; }

 private:
  BuildingParams params_;
  BuildingMesh mesh_;
  Eigen::SparseMatrix<double> k_;
  Eigen::VectorXd m_;
  std::vector<bool> foundation_node_;
  std::vector<int> free_index_, free_dofs_, constrained_dofs_;
  std::vector<ResponseNode> response_nodes_;
  std::array<std::vector<int>, 2> mirror_;
};

}  // namespace railvib::building
