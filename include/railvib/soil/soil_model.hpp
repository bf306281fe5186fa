// railvib/soil: the soil model as a stream processor — the whole computation
// of the soil node (the node only moves messages).
//
//   SoilModel model(params, params.track.sleeperPositions(), load_rate_hz);
//   model.pushLoads(first_index, forces, frames);   // [frame][sleeper], N, downward +, both rails
//   model.advance(t_target);                          // steps as far as the loads allow
//   model.takeReceiverSamples(block);                 // new receiver frames (filtered, receiver rate)
//   model.takeSnapshots(snaps);                       // new surface snapshots (snapshot rate)
//   ... model.finishLoads(); model.finishRun(t_end, slice); take...()
//
// Load sample n stands for time n / load_rate (n = 0 at t = 0); blocks must be
// contiguous (SampleIndexTracker, StreamGapError otherwise). With
// soil.loads.start_from_static (default) the run starts at static equilibrium
// under sample 0 (like the track model): the linear model is driven by
// F(t) - F(0), so velocities carry no start-up step (displacements are then
// relative to that static state). The loads are
// evaluated at the soil step times with the railvib/signal StreamInterpolator
// (cubic; the track already low-passed them). Receiver velocities (x, y, z up,
// m/s, frame `track`) go through the railvib/signal Decimator to
// receiver_rate_hz: output frame k stands for time k / receiver_rate exactly.
// Surface snapshots hold the vertical (up) velocity of every surface node,
// averaged over 1 / snapshot_rate centred on the snapshot time k / snapshot_rate.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "railvib/common/sample_stream.hpp"
#include "railvib/signal/decimator.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/solver.hpp"

namespace railvib::soil {

struct ReceiverBlock {
  uint64_t first_index = 0;  // output frame index of the first frame (time first_index / rate_hz)
  double rate_hz = 0.0;
  std::vector<std::string> names;  // receivers, in channel order
  /// frames x receivers x 3 (vx, vy, vz up), m/s, interleaved.
  std::vector<double> velocity_m_s;
  size_t frames() const { return names.empty() ? 0 : velocity_m_s.size() / (3 * names.size()); }
};

/// A snapshot's velocity fields, frame track: vx_m_s along the track, vy_m_s across it, vz_up_m_s up
/// (the horizontal ones empty when soil.output.snapshot_components is "vertical").
struct SnapshotVelocity {
  std::vector<float> vx_m_s, vy_m_s, vz_up_m_s;
  /// The field of component c (0 x, 1 y, 2 z up).
  std::vector<float>& component(int c) { return c == 0 ? vx_m_s : c == 1 ? vy_m_s : vz_up_m_s; }
};

/// The surface's velocity at the snapshot rate, box-averaged in time over [t - T/2, t + T/2).
/// Frame track: vx_m_s along the track, vy_m_s across it, vz_up_m_s up. The horizontal fields are
/// empty when soil.output.snapshot_components is "vertical".
struct SurfaceSnapshot : SnapshotVelocity {
  uint64_t index = 0;
  double time_s = 0.0;
  size_t nx_nodes = 0, ny_nodes = 0;  // x fastest
  double x0_m = 0.0, y0_m = 0.0, dx_m = 0.0, dy_m = 0.0;
};

/// The velocity on the vertical plane x = x_m (the node plane nearest to it) across the whole box:
/// y fastest, then depth; box-averaged in time and with the same components as SurfaceSnapshot
/// (paper, Fig. 16).
struct SectionSnapshot : SnapshotVelocity {
  uint64_t index = 0;
  double time_s = 0.0;
  double x_m = 0.0;
  size_t ny_nodes = 0;
  double y0_m = 0.0, dy_m = 0.0;
  std::vector<double> depth_m;  // node plane depths (m, down), one per row
};

/// The mesh's inclusions as meshed (name, kind, elements, how far snapping moved a face, the box in
/// frame track with depth down, the material's wave speeds), for run summaries and benchmarks.
nlohmann::json inclusionsSummary(const StructuredMesh& mesh);

class SoilModel {
 public:
  /// Builds the mesh and the solver, and attaches the rigid bodies (e.g. a house's foundation,
  /// coupling/house_foundation.hpp); sleepers outside the mesh, or reaching into the zone of a
  /// boundary that takes no loads (a PML), are an error or dropped (params.loads_outside_mesh).
  /// load_sample_rate_hz: rate of the load stream (the track's track.output.load_sample_rate_hz).
  /// Throws ConfigError / std::invalid_argument.
  /// comm: the ranks the soil is spread over (soil_comm.hpp; null = one rank). Spread over ranks, every
  /// rank constructs the model with the same arguments and calls the same methods in the same order
  /// (pushLoads, advance, finishRun, take*: they are collective); the take* results are complete on
  /// rank 0 only (SoilDriver, soil_driver.hpp, lets rank 0 alone be driven from outside).
  SoilModel(const SoilParams& params, const std::vector<double>& sleeper_x_m, double load_sample_rate_hz,
            const std::vector<RigidBodySpec>& bodies = {}, std::shared_ptr<SoilComm> comm = nullptr);
  /// The same with a force per rail seat (a full-width track): `rail_seat_y_m` are the lateral positions
  /// (m, frame track) of the seats on every sleeper, and a load frame holds [sleeper][seat] forces, each
  /// spread over its sleeper's footprint with its resultant at the seat (footprint.hpp,
  /// railSeatFootprint), so an asymmetric load reaches the soil as a force and a roll moment. Empty:
  /// one force per sleeper, both rails together, uniform over the footprint (the first constructor).
  /// Throws std::invalid_argument for a seat off the footprint (|y| > length / 2) or not finite.
  SoilModel(const SoilParams& params, const std::vector<double>& sleeper_x_m, const std::vector<double>& rail_seat_y_m,
            double load_sample_rate_hz, const std::vector<RigidBodySpec>& bodies = {},
            std::shared_ptr<SoilComm> comm = nullptr);
  ~SoilModel();

  const Solver& solver() const { return *solver_; }
  const SoilParams& params() const { return params_; }
  double dt() const { return solver_->dt(); }
  double time() const { return solver_->time(); }
  size_t sleeperCount() const { return sleeper_x_.size(); }
  /// Forces per sleeper in a load frame: 1, or the rail seats' count.
  size_t loadsPerSleeper() const { return seat_y_.empty() ? 1 : seat_y_.size(); }
  /// Forces per load frame: sleepers x loadsPerSleeper().
  size_t loadsPerFrame() const { return sleeperCount() * loadsPerSleeper(); }
  /// Sleepers whose load is ignored (outside the mesh or in a PML zone, loads_outside_mesh = drop).
  const std::vector<size_t>& droppedSleepers() const { return dropped_; }
  /// A sentence for the log when loads are dropped ("" when none): how many, where the loaded region
  /// ends, how many lie in a boundary zone, and how far the nearest dropped footprint is from a receiver.
  std::string droppedLoadsNote() const;
  const std::vector<ReceiverSpec>& receivers() const { return params_.receivers; }
  /// Mesh, time step, memory and per-layer resolution (printed by the tool).
  nlohmann::json summary() const;

  /// Append load frames [first_index, first_index + frames), row-major [frame][sleeper] (with rail
  /// seats [frame][sleeper][seat]).
  void pushLoads(uint64_t first_index, const double* forces_n, size_t frames);
  void pushLoads(uint64_t first_index, const std::vector<double>& forces_n) {
    pushLoads(first_index, forces_n.data(), forces_n.size() / loadsPerFrame());
  }
  /// No more loads: the last value is held.
  void finishLoads();
  /// Latest step time the loads received so far allow.
  double loadsAvailableUntil() const;
  /// Step while the step time t_n < t_target_s and the loads cover t_n. Returns steps taken.
  uint64_t advance(double t_target_s);
  /// End of run: flush the receiver decimator (emits the frames up to the current time).
  void finishOutputs();
  /// After finishLoads(): step to t_end_s (the last load sample's time) in slices of at most
  /// slice_s, calling after_slice() after each (outputs, progress; return false to stop early,
  /// e.g. on shutdown); then one step past t_end so the receiver frame at t_end exists (the last
  /// load is held), and finishOutputs(). Terminates whatever the rounding of the accumulated step
  /// time. Returns the steps taken.
  uint64_t finishRun(double t_end_s, double slice_s, const std::function<bool()>& after_slice = {});

  /// Move the receiver frames produced since the last call into `out` (replaces its content).
  void takeReceiverSamples(ReceiverBlock& out);
  /// Append the snapshots produced since the last call.
  void takeSnapshots(std::vector<SurfaceSnapshot>& out);
  /// Append the section snapshots produced since the last call (none unless soil.output.section).
  void takeSectionSnapshots(std::vector<SectionSnapshot>& out);

 private:
  void recordOutputs();
  void emitSnapshots();
  void sumToRoot(SnapshotVelocity& snapshot);
  bool spread() const;

  SoilParams params_;
  std::vector<double> sleeper_x_;
  std::vector<double> seat_y_;  // rail seats' lateral positions (m); empty: one force per sleeper
  std::vector<size_t> dropped_;
  size_t dropped_in_zone_ = 0;  // of those, inside the box but in a boundary zone that takes no loads (PML)
  double loaded_x_min_m_ = 0.0, loaded_x_max_m_ = 0.0;  // where footprints are loaded (box less such a zone)
  double dropped_nearest_receiver_m_ = 0.0;             // plan distance, dropped footprint to nearest receiver
  std::unique_ptr<Solver> solver_;
  std::unique_ptr<signal::StreamInterpolator> loads_;
  SampleIndexTracker load_tracker_{"soil_loads"};
  std::unique_ptr<signal::Decimator> rec_decimator_;
  std::vector<char> rec_owned_;  // per receiver: this rank computes it
  bool section_owned_ = true;
  std::vector<double> rec_prev_, rec_now_, rec_frame_, rec_out_;
  uint64_t rec_out_first_ = 0;
  // Snapshot averages, one block per recorded component (snap_components_: the solver's components,
  // internal frame with z down; {2} or {0, 1, 2}).
  std::vector<int> snap_components_;
  std::vector<double> surf_now_;
  std::vector<std::vector<double>> surf_prev_, surf_acc_;
  uint64_t snap_steps_ = 0, snap_count_ = 0, snap_acc_n_ = 0;
  std::vector<SurfaceSnapshot> snaps_;
  size_t section_i_ = 0;
  std::vector<std::vector<double>> sect_prev_, sect_acc_;
  std::vector<SectionSnapshot> section_snaps_;
  std::vector<double> channel_values_, load_eval_, first_frame_, shifted_;
  double load_t_offset_ = 0.0;
};

}  // namespace railvib::soil
