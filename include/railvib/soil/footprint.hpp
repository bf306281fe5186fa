// railvib/soil: a sleeper's footprint on the soil surface as consistent nodal loads, and the plan
// region where footprints may be loaded. One rule for every caller: the chain's soil model
// (soil_model.hpp) and the soil's compliance between footprints (footprint_compliance.hpp).
#pragma once

#include "railvib/common/site.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

/// A uniform unit vertical (downward) force over the footprint of the sleeper at x_m, centred on the
/// track axis y = 0 (length across the track, width along it: TrackLayout), as consistent nodal loads
/// of the surface nodes (bilinear hat functions): the weights sum to 1 when the footprint lies inside
/// the mesh. The same weights, applied to the surface displacements, give the footprint's
/// work-conjugate (load-weighted mean) displacement.
ForceChannel sleeperFootprint(const StructuredMesh& mesh, double x_m, const TrackLayout& layout);

/// A unit vertical (downward) force at the rail seat y = seat_y_m of the sleeper at x_m, spread over the
/// sleeper's footprint as the linear pressure whose resultant acts at the seat (a rigid sleeper on a
/// uniform bed: p(y) = (1 / L + 12 seat_y y / L^3) / W over the footprint L x W): the weights sum to
/// 1 and their first moment in y is seat_y_m. The two seats' channels of a sleeper, loaded alike,
/// add up to the uniform footprint under twice the load (sleeperFootprint), to round-off; loaded
/// in anti-phase, to a pure roll moment.
ForceChannel railSeatFootprint(const StructuredMesh& mesh, double x_m, double seat_y_m, const TrackLayout& layout);

/// The footprint's load-weighted mean of a nodal field component: sum_n w_n value(node_n, c).
template <class NodalValue>
double footprintMean(const ForceChannel& footprint, NodalValue&& value) {
  double sum = 0.0;
  for (size_t n = 0; n < footprint.nodes.size(); ++n) {
    sum += footprint.weights[n] * value(footprint.nodes[n], footprint.components[n]);
  }
  return sum;
}

/// The plan region where footprints take loads: the mesh box less the zone of an absorbing face whose
/// boundary zone takes no loads (a PML: its fields are not physical). `faces`: the whole mesh's
/// absorbing faces (the solver's own options hold its slab's, spread over ranks).
struct LoadableRegion {
  double x_min_m = 0.0, x_max_m = 0.0, y_min_m = 0.0, y_max_m = 0.0;
  /// The zone the region leaves out on each absorbing face (m; 0 when the zone takes loads).
  double zone_m = 0.0;
  /// Whether the footprint of the sleeper at x_m lies in the region (1e-9 m tolerance).
  bool holds(double x_m, const TrackLayout& layout) const;
};
LoadableRegion loadableRegion(const Solver& solver, const AbsorbingFaces& faces);

/// Whether the footprint of the sleeper at x_m lies inside the mesh box (1e-9 m tolerance).
bool footprintInsideMesh(const StructuredMesh& mesh, double x_m, const TrackLayout& layout);

}  // namespace railvib::soil
