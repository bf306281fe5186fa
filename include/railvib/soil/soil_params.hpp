// railvib/soil: parameters of the soil model, read from the merged config.
#pragma once

#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

/// A named output point, frame `track` (x along, y towards the building, z up; z = 0 surface).
struct ReceiverSpec {
  std::string name;
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
};

struct SoilParams {
  std::vector<Layer> profile;  // layers then the half-space (last)
  MeshSpec mesh;
  SolverOptions solver;
  double max_memory_gb = 12.0;
  double receiver_rate_hz = 1000.0;
  double snapshot_rate_hz = 100.0;
  /// Vertical section x = section_x_m recorded at the snapshot rate (paper, Fig. 16), if enabled.
  bool section_enabled = false;
  double section_x_m = 0.0;
  /// Sleeper footprint on the surface, centred on the track axis (y = 0).
  double sleeper_length_m = 2.6, sleeper_width_m = 0.25;
  /// Sleeper positions rule of the track model: offset + k * spacing within the extent.
  double sleeper_spacing_m = 0.72, sleeper_offset_m = 0.0, track_x_min_m = -40.0, track_x_max_m = 40.0;
  /// Sleepers whose footprint is not inside the mesh: "error" or "drop" (their load is ignored, reported).
  std::string loads_outside_mesh = "error";
  /// Start from static equilibrium under the first load sample: the model is linear, so the
  /// velocities are those of the load increments F(t) - F(0) from rest (no start-up step).
  bool start_from_static = true;
  double load_sample_rate_hz = 2000.0;
  double duration_s = 5.0;
  std::vector<ReceiverSpec> receivers;

  /// Sleeper x positions by the track model's rule.
  std::vector<double> sleeperPositions() const;
};

/// Read `soil`, and the keys it needs from `track`, `site`, `building`, `simulation`.
/// Throws ConfigError (key path, value, range, file) on bad input, including
/// receivers outside the mesh box and a mesh that would not fit in max_memory_gb.
SoilParams loadSoilParams(const ConfigNode& root);

}  // namespace railvib::soil
