// railvib/soil: compact binary file of surface snapshots (vertical velocity).
//
// Layout (little-endian):
//   char[8]  "RVBSNAP1"
//   uint64   nx_nodes, ny_nodes            (x fastest)
//   float64  x0_m, y0_m, dx_m, dy_m        (node (i, j) at x0 + i dx, y0 + j dy; frame `track`, z = 0)
//   uint64   snapshot count
//   then per snapshot: uint64 index, float64 time_s, float32[nx_nodes * ny_nodes] vz_up_m_s
// Python: see docs/soil.md (numpy.fromfile with the header offsets).
#pragma once

#include <string>
#include <vector>

#include "railvib/soil/soil_model.hpp"

namespace railvib::soil {

/// Write snapshots atomically (all must share one grid). Throws std::runtime_error.
void writeSnapshots(const std::string& path, const std::vector<SurfaceSnapshot>& snapshots);
/// Read a snapshot file back. Throws std::runtime_error on a malformed file.
std::vector<SurfaceSnapshot> readSnapshots(const std::string& path);

/// Vertical section snapshots: "RVBSECT1", uint64 ny_nodes, uint64 planes, float64 x_m, y0_m, dy_m,
/// float64[planes] depths (m, down), uint64 count, then per snapshot uint64 index, float64 time_s,
/// float32[ny_nodes * planes] vz_up_m_s (y fastest, then depth).
void writeSectionSnapshots(const std::string& path, const std::vector<SectionSnapshot>& snapshots);
std::vector<SectionSnapshot> readSectionSnapshots(const std::string& path);

}  // namespace railvib::soil
