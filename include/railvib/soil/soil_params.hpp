// railvib/soil: parameters of the soil model, read from the merged config.
#pragma once

#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/common/site.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

/// A named output point, frame `track` (x along, y towards the building, z up; z = 0 surface).
struct ReceiverSpec {
  std::string name;
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  /// Where it comes from (a config key path), for error messages.
  std::string origin;
};

/// Receivers the house asks the soil for (frame track, on the surface), named by the building
/// domain: its free field (building::freeFieldPoints; kept if soil.output.building_receivers) and
/// the footprint points that drive its foundation (building::footprintPoints).
struct HouseReceivers {
  std::vector<NamedPoint> free_field;
  std::vector<NamedPoint> footprint;
};

struct SoilParams {
  std::vector<Layer> profile;  // layers then the half-space (last)
  MeshSpec mesh;
  /// soil.mesh.extent mode auto: the box's plan fitted to the site (receivers, inclusions, section,
  /// the sleepers across the track) with these margins and the absorbing zone; false: as given.
  bool box_fitted = false;
  double box_margin_along_m = 0.0;
  double box_margin_across_m = 0.0;
  SolverOptions solver;
  double max_memory_gb = 12.0;
  double receiver_rate_hz = 1000.0;
  double snapshot_rate_hz = 100.0;
  /// Snapshots carry the horizontal velocity too (soil.output.snapshot_components: all), or the
  /// vertical only ("vertical": a third of the snapshot bytes in a bag).
  bool snapshot_horizontal = true;
  /// Vertical section x = section_x_m recorded at the snapshot rate (paper, Fig. 16), if enabled.
  bool section_enabled = false;
  double section_x_m = 0.0;
  /// The sleepers (positions rule and footprint on the surface, centred on the track axis y = 0).
  TrackLayout track;
  /// Sleepers whose footprint is not inside the mesh: "error" or "drop" (their load is ignored;
  /// SoilModel::droppedSleepers lists them).
  std::string loads_outside_mesh = "error";
  /// With "drop": a dropped sleeper footprint nearer than this (m, plan distance) to a receiver is an
  /// error, so that no load is dropped in the zone of interest.
  double drop_min_receiver_distance_m = 0.0;
  /// Start from static equilibrium under the first load sample: the model is linear, so the
  /// velocities are those of the load increments F(t) - F(0) from rest (no start-up step).
  bool start_from_static = true;
  /// Ground sensors (site.ground_sensors and the placed free-field sensors), the receiver line, then the house's
  /// receivers.
  std::vector<ReceiverSpec> receivers;
};

/// Read `soil`, the track layout and the site's ground sensors, and add the house's receivers.
/// Throws ConfigError (key path, value, range, file) on bad input, including receivers outside the
/// mesh box or in its absorbing layer, and a mesh that would not fit in max_memory_gb.
SoilParams loadSoilParams(const ConfigNode& root, const HouseReceivers& house = {});
/// soil.output.receiver_rate_hz alone (the rate of the soil's velocity stream, for its consumers),
/// read by the same rule as loadSoilParams, without building the mesh.
double loadReceiverRateHz(const ConfigNode& root);
/// soil.mesh.f_max_hz alone (the highest frequency the soil resolves: verdicts whose governing frequency
/// lies above it are not assessable), read by the same rule as loadSoilParams.
double loadResolvedFrequencyHz(const ConfigNode& root);

}  // namespace railvib::soil
