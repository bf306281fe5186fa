// railvib/soil: slab decomposition of the soil mesh (partition.hpp).
#include "railvib/soil/partition.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace railvib::soil {

int SlabPartition::ownerOfColumn(size_t i) const {
  for (int r = 0; r < ranks; ++r) {
    if (i < cuts[static_cast<size_t>(r) + 1]) return r;
  }
  return ranks - 1;
}

SlabPartition makeSlabPartition(size_t nx, int ranks, int rank, size_t min_columns, size_t min_end_columns) {
  if (ranks < 1) throw std::invalid_argument("soil partition: " + std::to_string(ranks) + " ranks");
  if (rank < 0 || rank >= ranks) {
    throw std::invalid_argument("soil partition: rank " + std::to_string(rank) + " of " + std::to_string(ranks));
  }
  SlabPartition p;
  p.ranks = ranks;
  p.rank = rank;
  p.cuts.resize(static_cast<size_t>(ranks) + 1);
  const size_t n = static_cast<size_t>(ranks);
  for (size_t r = 0; r <= n; ++r) p.cuts[r] = (nx * r + n / 2) / n;
  p.cuts[n] = nx;
  if (ranks == 1) return p;
  const size_t need_end = std::max(min_columns, min_end_columns);
  for (size_t r = 0; r < n; ++r) {
    const size_t have = p.cuts[r + 1] - p.cuts[r];
    const bool end_slab = r == 0 || r + 1 == n;
    const size_t need = end_slab ? need_end : min_columns;
    if (have < need) {
      std::ostringstream why;
      why << "soil partition: " << ranks << " ranks do not fit the mesh: its " << nx
          << " element columns along x give slab " << r << " only " << have << " columns, it needs at least " << need
          << (end_slab ? " (an end slab holds the boundary layer along x, plus one column)" : "") << "; at most "
          << std::max<size_t>(1, nx / need_end) << " ranks fit this mesh";
      throw std::invalid_argument(why.str());
    }
  }
  return p;
}

StructuredMesh sliceMesh(const StructuredMesh& mesh, size_t i0, size_t i1) {
  if (!(i0 < i1) || i1 > mesh.nx) {
    throw std::invalid_argument("soil partition: slab [" + std::to_string(i0) + ", " + std::to_string(i1) +
                                ") outside the mesh's " + std::to_string(mesh.nx) + " columns");
  }
  StructuredMesh s = mesh;
  s.nx = i1 - i0;
  s.x0 = mesh.x(i0);
  // The inclusions' parts in the slab, in its column indices.
  s.inclusions.clear();
  for (const MeshInclusion& inc : mesh.inclusions) {
    ElementBox part = inc.elements.intersect({i0, i1, 0, mesh.ny, 0, mesh.nz});
    if (part.empty()) continue;
    MeshInclusion local = inc;
    local.elements = {part.i0 - i0, part.i1 - i0, part.j0, part.j1, part.k0, part.k1};
    s.inclusions.push_back(std::move(local));
  }
  return s;
}

std::string describePartition(const SlabPartition& p) {
  std::ostringstream out;
  out << p.ranks << (p.ranks == 1 ? " rank" : " ranks") << ", element columns";
  for (int r = 0; r < p.ranks; ++r)
    out << " [" << p.cuts[static_cast<size_t>(r)] << ", " << p.cuts[static_cast<size_t>(r) + 1] << ")";
  return out.str();
}

void mapToSlab(const std::vector<size_t>& global_nodes, const StructuredMesh& global_mesh, const StructuredMesh& slab,
               const SlabPartition& partition, std::vector<size_t>& local, std::vector<char>& owned) {
  const size_t sx = global_mesh.nx + 1, sxy = sx * (global_mesh.ny + 1);
  local.assign(global_nodes.size(), kNotInSlab);
  owned.assign(global_nodes.size(), 0);
  for (size_t a = 0; a < global_nodes.size(); ++a) {
    const size_t g = global_nodes[a];
    const size_t i = g % sx, j = (g % sxy) / sx, k = g / sxy;
    owned[a] = partition.ownsNodePlane(i) ? 1 : 0;
    if (partition.holdsNodePlane(i)) local[a] = slab.node(i - partition.begin(), j, k);
  }
}

}  // namespace railvib::soil
