// railvib/soil: the domain decomposition of the soil mesh over ranks (soil_comm.hpp).
//
// The mesh is cut into slabs of whole element columns along x (the track): rank r
// integrates the elements with column index i in [cuts[r], cuts[r+1]) and holds
// the node planes cuts[r] .. cuts[r+1]. Two neighbouring slabs share one node
// plane: each rank adds the forces of its own elements there and the two partial
// sums are exchanged every step, so both ranks update that plane identically
// (a + b = b + a in floating point). For outputs and point loads every node plane
// has one owner: rank r owns planes [cuts[r], cuts[r+1]), the last rank also nx.
// Slabs along x keep every rank's halo the same size, (ny + 1)(nz + 1) nodes per
// side, and the boundary layers along y and the bottom are split evenly.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"

namespace railvib::soil {

struct SlabPartition {
  int ranks = 1, rank = 0;
  std::vector<size_t> cuts{0, 0};  // ranks + 1 element-column indices, cuts[0] = 0, cuts[ranks] = nx

  bool single() const { return ranks == 1; }
  size_t begin() const { return cuts[static_cast<size_t>(rank)]; }  // first element column of this slab
  size_t end() const { return cuts[static_cast<size_t>(rank) + 1]; }
  size_t columns() const { return end() - begin(); }
  bool hasLow() const { return rank > 0; }
  bool hasHigh() const { return rank + 1 < ranks; }
  /// Whether this rank owns global node plane i (outputs, point loads).
  bool ownsNodePlane(size_t i) const { return i >= begin() && (i < end() || (!hasHigh() && i == end())); }
  /// Whether global node plane i lies in this slab (owned or shared).
  bool holdsNodePlane(size_t i) const { return i >= begin() && i <= end(); }
  /// Rank whose slab holds element column i.
  int ownerOfColumn(size_t i) const;
};

/// Balanced slabs (column counts differ by at most one) of a mesh with nx element columns.
/// `min_end_columns`: the least columns of the first and last slab (e.g. a boundary layer plus one),
/// `min_columns` of the others. Throws std::invalid_argument naming the counts when the ranks do not fit.
SlabPartition makeSlabPartition(size_t nx, int ranks, int rank, size_t min_columns, size_t min_end_columns);

/// The slab [i0, i1) of element columns of a mesh, as a mesh of its own (x0 moved, the rest kept).
StructuredMesh sliceMesh(const StructuredMesh& mesh, size_t i0, size_t i1);

/// Where whole-mesh nodes (`global_nodes`, node indices of `global_mesh`) are on this rank: `local[a]` their
/// index in `slab` (kNotInSlab when the slab does not hold their node plane), `owned[a]` 1 when this rank
/// owns their plane (it alone contributes their values to a sum over ranks).
constexpr size_t kNotInSlab = static_cast<size_t>(-1);
void mapToSlab(const std::vector<size_t>& global_nodes, const StructuredMesh& global_mesh, const StructuredMesh& slab,
               const SlabPartition& partition, std::vector<size_t>& local, std::vector<char>& owned);

/// Partition summary line for logs: "2 ranks, element columns [0, 57) [57, 113)".
std::string describePartition(const SlabPartition& p);

}  // namespace railvib::soil
