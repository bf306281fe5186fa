#include "railvib/soil/soil_model.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "railvib/soil/footprint.hpp"

namespace railvib::soil {

SoilModel::SoilModel(const SoilParams& params, const std::vector<double>& sleeper_x_m, double load_sample_rate_hz,
                     const std::vector<RigidBodySpec>& bodies, std::shared_ptr<SoilComm> comm)
    : SoilModel(params, sleeper_x_m, {}, load_sample_rate_hz, bodies, std::move(comm)) {}

SoilModel::SoilModel(const SoilParams& params, const std::vector<double>& sleeper_x_m,
                     const std::vector<double>& rail_seat_y_m, double load_sample_rate_hz,
                     const std::vector<RigidBodySpec>& bodies, std::shared_ptr<SoilComm> comm)
    : params_(params), sleeper_x_(sleeper_x_m), seat_y_(rail_seat_y_m) {
  for (double y : seat_y_) {
    if (!(std::abs(y) <= 0.5 * params_.track.length_m)) {
      std::ostringstream why;
      why << "soil: a rail seat at y = " << y << " m lies off the sleeper's footprint (length "
          << params_.track.length_m << " m across the track)";
      throw std::invalid_argument(why.str());
    }
  }
  StructuredMesh mesh = buildMesh(params_.profile, params_.mesh);
  solver_ = std::make_unique<Solver>(std::move(mesh), params_.solver, std::move(comm));
  for (const RigidBodySpec& b : bodies) solver_->attachRigidBody(b);
  const StructuredMesh& m = solver_->mesh();
  // Sleeper footprints -> consistent nodal loads (downward = +d); the loaded region leaves out a
  // boundary zone that takes no loads (footprint.hpp).
  const LoadableRegion region = loadableRegion(*solver_, params_.solver.absorbing);
  const double zone = region.zone_m;
  const double lx0 = region.x_min_m, lx1 = region.x_max_m;
  std::vector<size_t> outside;
  size_t in_zone = 0;
  for (size_t s = 0; s < sleeper_x_.size(); ++s) {
    if (!region.holds(sleeper_x_[s], params_.track)) {
      if (footprintInsideMesh(m, sleeper_x_[s], params_.track)) ++in_zone;
      outside.push_back(s);
      continue;
    }
    if (seat_y_.empty()) {
      solver_->addForceChannel(sleeperFootprint(m, sleeper_x_[s], params_.track));
    } else {
      for (double y : seat_y_) solver_->addForceChannel(railSeatFootprint(m, sleeper_x_[s], y, params_.track));
    }
  }
  if (!outside.empty() && params_.loads_outside_mesh == "error") {
    std::ostringstream why;
    why << outside.size() << " sleeper footprints (e.g. x = " << sleeper_x_[outside.front()]
        << " m) lie outside the soil mesh x [" << m.x0 << ", " << m.xMax() << "] m";
    if (in_zone > 0) {
      why << " or in the " << zone << " m " << boundaryMethodName(solver_->boundary().method()) << " zone";
    }
    why << "; widen soil.mesh or set soil.loads.outside_mesh: drop";
    throw ConfigError("soil.loads.outside_mesh: " + why.str());
  }
  dropped_ = outside;
  dropped_in_zone_ = in_zone;
  loaded_x_min_m_ = lx0;
  loaded_x_max_m_ = lx1;
  dropped_nearest_receiver_m_ = std::numeric_limits<double>::infinity();
  for (size_t s : dropped_) {
    for (const ReceiverSpec& r : params_.receivers) {
      // Plan distance from the receiver to the footprint rectangle.
      const double hl = 0.5 * params_.track.length_m, hw = 0.5 * params_.track.width_m;
      const double dx = std::max(0.0, std::abs(r.x_m - sleeper_x_[s]) - hw);
      const double dy = std::max(0.0, std::abs(r.y_m) - hl);
      const double distance_m = std::hypot(dx, dy);
      if (distance_m < params_.drop_min_receiver_distance_m) {
        std::ostringstream why;
        why << "the sleeper at x = " << sleeper_x_[s] << " m lies outside the loaded region x [" << lx0 << ", " << lx1
            << "] m of the soil mesh, " << distance_m << " m from receiver '" << r.name
            << "', nearer than drop_min_receiver_distance_m = " << params_.drop_min_receiver_distance_m
            << " m: its load would be dropped in the zone of interest; widen soil.mesh along x";
        throw ConfigError("soil.loads.drop_min_receiver_distance_m: " + why.str());
      }
      dropped_nearest_receiver_m_ = std::min(dropped_nearest_receiver_m_, distance_m);
    }
  }
  channel_values_.assign((sleeper_x_.size() - dropped_.size()) * loadsPerSleeper(), 0.0);
  load_eval_.assign(loadsPerFrame(), 0.0);
  loads_ = std::make_unique<signal::StreamInterpolator>(load_sample_rate_hz, loadsPerFrame(), 0.0);

  const double ratio = std::round(1.0 / (solver_->dt() * params_.receiver_rate_hz));
  signal::DecimatorSpec spec;
  spec.input_rate_hz = ratio * params_.receiver_rate_hz;
  spec.output_rate_hz = params_.receiver_rate_hz;
  if (!params_.receivers.empty()) {
    rec_decimator_ = std::make_unique<signal::Decimator>(spec, 3 * params_.receivers.size(), 0.0);
  }
  for (const ReceiverSpec& r : params_.receivers) rec_owned_.push_back(solver_->ownsPoint(r.x_m) ? 1 : 0);
  rec_prev_.assign(3 * params_.receivers.size(), 0.0);
  rec_now_ = rec_prev_;
  rec_frame_ = rec_prev_;
  snap_steps_ = static_cast<uint64_t>(std::llround(ratio * params_.receiver_rate_hz / params_.snapshot_rate_hz));
  snap_components_ = params_.snapshot_horizontal ? std::vector<int>{0, 1, 2} : std::vector<int>{2};
  const size_t ns = (m.nx + 1) * (m.ny + 1);
  surf_prev_.assign(snap_components_.size(), std::vector<double>(ns, 0.0));
  surf_acc_ = surf_prev_;
  if (params_.section_enabled) {
    section_i_ =
        static_cast<size_t>(std::clamp(std::lround((params_.section_x_m - m.x0) / m.hx), 0L, static_cast<long>(m.nx)));
    section_owned_ = solver_->ownsNodePlane(section_i_);
    sect_prev_.assign(snap_components_.size(), std::vector<double>((m.ny + 1) * (m.nz + 1), 0.0));
    sect_acc_ = sect_prev_;
  }
}

SoilModel::~SoilModel() = default;

namespace {
nlohmann::json bodiesSummary(const Solver& s) {
  nlohmann::json out = nlohmann::json::array();
  for (size_t i = 0; i < s.rigidBodyCount(); ++i) {
    const RigidBodyState& b = s.rigidBody(i);
    out.push_back({{"carried_nodes", b.carried_nodes},
                   {"carried_soil_mass_kg", b.carried_soil_mass_kg},
                   {"total_mass_kg", b.total_mass_kg},
                   {"region_m", {{b.x_min_m, b.x_max_m}, {b.y_min_m, b.y_max_m}, {0.0, b.depth_m}}},
                   {"modes", b.modal_displacement.size()}});
  }
  return out;
}
}  // namespace

nlohmann::json inclusionsSummary(const StructuredMesh& m) {
  nlohmann::json out = nlohmann::json::array();
  for (const MeshInclusion& inc : m.inclusions) {
    nlohmann::json j = {{"name", inc.name},
                        {"kind", inc.is_void ? "void" : "material"},
                        {"elements", inc.elements.count()},
                        {"moved_m", inc.moved_m},
                        {"x_m", {m.x(inc.elements.i0), m.x(inc.elements.i1)}},
                        {"y_m", {m.y(inc.elements.j0), m.y(inc.elements.j1)}},
                        {"depth_m", {m.z[inc.elements.k0], m.z[inc.elements.k1]}}};
    if (!inc.is_void) {
      j["vs_m_s"] = inc.material.vs();
      j["vp_m_s"] = inc.material.vp();
      if (inc.rayleigh_beta_s >= 0.0) j["rayleigh_beta_s"] = inc.rayleigh_beta_s;
      j["integration"] = inc.implicit ? "implicit" : "explicit";
    }
    out.push_back(j);
  }
  return out;
}

namespace {
// The implicit inclusions' solve (docs/soil.md, "Implicit inclusions"), null without one.
nlohmann::json implicitSolveSummary(const Solver& s) {
  const Solver::ImplicitSolveInfo info = s.implicitSolve();
  if (info.unknowns == 0) return nullptr;
  return {{"unknowns", info.unknowns},
          {"factor_nonzeros", info.factor_nonzeros},
          {"parts", {info.part_0, info.part_1}},
          {"separator", info.separator}};
}
}  // namespace

nlohmann::json SoilModel::summary() const {
  const Solver& s = *solver_;
  const StructuredMesh& m = s.mesh();
  nlohmann::json layers = nlohmann::json::array();
  for (const auto& l : m.layers) {
    layers.push_back({{"top_m", l.top_m},
                      {"bottom_m", l.bottom_m},
                      {"levels", l.levels},
                      {"dz_m", l.dz_m},
                      {"vs_m_s", l.material.vs()},
                      {"vp_m_s", l.material.vp()},
                      {"resolved_hz", l.resolved_hz}});
  }
  // The snapshot averages: previous and sum per component, plus one field read from the solver.
  auto fieldBytes = [](const std::vector<std::vector<double>>& fields) {
    size_t n = 0;
    for (const auto& f : fields) n += f.capacity() * sizeof(double);
    return n;
  };
  const size_t snapshot_bytes = fieldBytes(surf_prev_) + fieldBytes(surf_acc_) + fieldBytes(sect_prev_) +
                                fieldBytes(sect_acc_) + (m.nx + 1) * (m.ny + 1) * sizeof(double);
  return {{"elements", m.elementCount()},
          {"nodes", m.nodeCount()},
          {"dofs", 3 * m.nodeCount()},
          {"nx", m.nx},
          {"ny", m.ny},
          {"nz", m.nz},
          {"hx_m", m.hx},
          {"hy_m", m.hy},
          {"box_m", {{m.x0, m.xMax()}, {m.y0, m.yMax()}, {0.0, m.depth()}}},
          {"layers", layers},
          {"inclusions", inclusionsSummary(m)},
          {"boundary", s.boundary().summary()},
          {"kernel", kernelName(s.kernel())},
          {"dt_s", s.dt()},
          {"dt_undamped_limit_s", s.dtUndamped()},
          {"dt_filtered_rayleigh_limit_s", s.dtDamped()},
          {"dt_naive_rayleigh_limit_s", s.dtNaiveRayleigh()},
          {"precision", s.options().precision == Precision::Float ? "float" : "double"},
          {"threads", s.options().threads > 0 ? s.options().threads : omp_get_max_threads()},
          {"memory_bytes", s.memoryBytes() + snapshot_bytes},  // of this rank
          {"sleepers_loaded", sleeper_x_.size() - dropped_.size()},
          {"sleepers_dropped", dropped_.size()},
          {"sleepers_dropped_in_boundary_zone", dropped_in_zone_},
          {"loaded_x_m", {loaded_x_min_m_, loaded_x_max_m_}},
          {"dropped_nearest_receiver_m", dropped_.empty() || params_.receivers.empty()
                                             ? nlohmann::json(nullptr)
                                             : nlohmann::json(dropped_nearest_receiver_m_)},
          {"receivers", params_.receivers.size()},
          {"ranks", s.partition().ranks},
          {"partition", describePartition(s.partition())},
          {"local_elements", s.localMesh().elementCount()},
          {"rigid_bodies", bodiesSummary(s)},
          {"implicit_solve", implicitSolveSummary(s)}};
}

std::string SoilModel::droppedLoadsNote() const {
  if (dropped_.empty()) return "";
  std::ostringstream note;
  note << dropped_.size() << " of " << sleeper_x_.size() << " sleepers lie outside the loaded region x ["
       << loaded_x_min_m_ << ", " << loaded_x_max_m_ << "] m";
  if (dropped_in_zone_ > 0) {
    note << " (" << dropped_in_zone_ << " of them in the " << solver_->boundary().zoneThicknessM() << " m "
         << boundaryMethodName(solver_->boundary().method()) << " zone)";
  }
  note << ": their loads are not applied";
  if (!params_.receivers.empty()) note << "; the nearest is " << dropped_nearest_receiver_m_ << " m from a receiver";
  return note.str();
}

void SoilModel::pushLoads(uint64_t first_index, const double* forces_n, size_t frames) {
  load_tracker_.accept(first_index, frames);
  const size_t ns = loadsPerFrame();
  if (!params_.start_from_static) {
    loads_->push(forces_n, frames);
    return;
  }
  if (first_frame_.empty() && frames > 0) first_frame_.assign(forces_n, forces_n + ns);
  shifted_.resize(frames * ns);
  for (size_t f = 0; f < frames; ++f) {
    for (size_t s = 0; s < ns; ++s) shifted_[f * ns + s] = forces_n[f * ns + s] - first_frame_[s];
  }
  loads_->push(shifted_.data(), frames);
}

void SoilModel::finishLoads() { loads_->finish(); }

double SoilModel::loadsAvailableUntil() const { return loads_->availableUntil(); }

uint64_t SoilModel::advance(double t_target_s) {
  uint64_t n = 0;
  while (solver_->time() < t_target_s - 1e-9 * solver_->dt() && loads_->canEvaluate(solver_->time())) {
    loads_->evaluate(solver_->time(), load_eval_.data());
    size_t c = 0, d = 0;
    const size_t per = loadsPerSleeper();
    for (size_t s = 0; s < sleeper_x_.size(); ++s) {
      if (d < dropped_.size() && dropped_[d] == s) {
        ++d;
        continue;
      }
      for (size_t k = 0; k < per; ++k) channel_values_[c++] = load_eval_[s * per + k];
    }
    solver_->setChannelValues(channel_values_);
    solver_->step();
    recordOutputs();
    ++n;
    if ((solver_->stepCount() & 255) == 0) loads_->discardBefore(solver_->time());
  }
  return n;
}

void SoilModel::recordOutputs() {
  // Half-step velocities -> values at t_n = (stepCount - 1) dt by averaging.
  const auto& rec = params_.receivers;
  for (size_t r = 0; r < rec.size(); ++r) {
    double v[3] = {0.0, 0.0, 0.0};  // another rank's receiver: 0 here, its value after the sum on rank 0
    if (rec_owned_[r]) solver_->velocityAt(rec[r].x_m, rec[r].y_m, -rec[r].z_m, v);
    rec_now_[3 * r] = v[0];
    rec_now_[3 * r + 1] = v[1];
    rec_now_[3 * r + 2] = -v[2];
  }
  for (size_t q = 0; q < rec_now_.size(); ++q) rec_frame_[q] = 0.5 * (rec_prev_[q] + rec_now_[q]);
  rec_prev_.swap(rec_now_);
  if (rec_decimator_) rec_decimator_->push(rec_frame_.data(), 1, rec_out_);

  // Snapshots: box mean over [t_k - T/2, t_k + T/2) of the velocity, frame track (z up).
  const uint64_t n = solver_->stepCount() - 1;  // the frame just completed stands for t_n
  const uint64_t k = (n + snap_steps_ / 2) / snap_steps_;
  if (k != snap_count_) emitSnapshots();
  snap_count_ = k;
  const StructuredMesh& m = solver_->mesh();
  for (size_t q = 0; q < snap_components_.size(); ++q) {
    const int c = snap_components_[q];
    const double to_track = c == 2 ? -1.0 : 1.0;  // internal z is down
    solver_->surfaceVelocity(c, surf_now_);
    std::vector<double>& prev = surf_prev_[q];
    std::vector<double>& acc = surf_acc_[q];
    for (size_t i = 0; i < acc.size(); ++i) acc[i] += to_track * 0.5 * (prev[i] + surf_now_[i]);
    prev.swap(surf_now_);
    if (params_.section_enabled && section_owned_) {
      size_t p = 0;
      for (size_t kz = 0; kz <= m.nz; ++kz) {
        for (size_t j = 0; j <= m.ny; ++j, ++p) {
          const double v_now = solver_->velocity(m.node(section_i_, j, kz), c);
          sect_acc_[q][p] += to_track * 0.5 * (sect_prev_[q][p] + v_now);
          sect_prev_[q][p] = v_now;
        }
      }
    }
  }
  ++snap_acc_n_;
}

namespace {
// The mean of an accumulated field, into the snapshot's field of the same component; the sum restarts.
void takeMean(std::vector<double>& acc, uint64_t count, int component, SnapshotVelocity& snapshot) {
  std::vector<float>& out = snapshot.component(component);
  out.resize(acc.size());
  for (size_t i = 0; i < acc.size(); ++i) out[i] = static_cast<float>(acc[i] / static_cast<double>(count));
  std::fill(acc.begin(), acc.end(), 0.0);
}
}  // namespace

void SoilModel::emitSnapshots() {
  const StructuredMesh& m = solver_->mesh();
  SurfaceSnapshot s;
  s.index = snap_count_;
  s.time_s = static_cast<double>(snap_count_) / params_.snapshot_rate_hz;
  s.nx_nodes = m.nx + 1;
  s.ny_nodes = m.ny + 1;
  s.x0_m = m.x0;
  s.y0_m = m.y0;
  s.dx_m = m.hx;
  s.dy_m = m.hy;
  for (size_t q = 0; q < snap_components_.size(); ++q) {
    takeMean(surf_acc_[q], snap_acc_n_, snap_components_[q], s);
  }
  snaps_.push_back(std::move(s));
  if (params_.section_enabled) {
    SectionSnapshot c;
    c.index = snap_count_;
    c.time_s = static_cast<double>(snap_count_) / params_.snapshot_rate_hz;
    c.x_m = m.x(section_i_);
    c.ny_nodes = m.ny + 1;
    c.y0_m = m.y0;
    c.dy_m = m.hy;
    c.depth_m = m.z;
    for (size_t q = 0; q < snap_components_.size(); ++q) {
      takeMean(sect_acc_[q], snap_acc_n_, snap_components_[q], c);
    }
    section_snaps_.push_back(std::move(c));
  }
  snap_acc_n_ = 0;
}

void SoilModel::finishOutputs() {
  if (rec_decimator_ && !rec_decimator_->flushed()) rec_decimator_->flush(rec_out_);
}

uint64_t SoilModel::finishRun(double t_end_s, double slice_s, const std::function<bool()>& after_slice) {
  if (!loads_->finished()) throw std::logic_error("SoilModel::finishRun before finishLoads");
  if (!(slice_s > 0.0)) throw std::invalid_argument("SoilModel::finishRun: slice_s must be > 0");
  uint64_t steps = 0;
  while (time() < t_end_s) {
    // advance() stops within 1e-9 dt of its target: no step taken means t_end is reached.
    const uint64_t n = advance(std::min(t_end_s, time() + slice_s));
    if (n == 0) break;
    steps += n;
    if (after_slice && !after_slice()) return steps;
  }
  steps += advance(t_end_s + dt());
  finishOutputs();
  return steps;
}

void SoilModel::takeReceiverSamples(ReceiverBlock& out) {
  out.first_index = rec_out_first_;
  out.rate_hz = params_.receiver_rate_hz;
  out.names.clear();
  for (const auto& r : params_.receivers) out.names.push_back(r.name);
  out.velocity_m_s.swap(rec_out_);
  rec_out_.clear();
  // Every rank holds its own receivers' frames and zeros for the others: the sum is the block.
  if (spread() && !out.velocity_m_s.empty())
    solver_->comm().sumToRoot(out.velocity_m_s.data(), out.velocity_m_s.size());
  rec_out_first_ += out.frames();
}

bool SoilModel::spread() const { return !solver_->partition().single(); }

// Every rank holds its own nodes' values and zeros for the others: the sum on rank 0 is the field.
void SoilModel::sumToRoot(SnapshotVelocity& snapshot) {
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& field = snapshot.component(c);
    if (!field.empty()) solver_->comm().sumToRoot(field.data(), field.size());
  }
}

void SoilModel::takeSnapshots(std::vector<SurfaceSnapshot>& out) {
  for (auto& s : snaps_) {
    if (spread()) sumToRoot(s);
    out.push_back(std::move(s));
  }
  snaps_.clear();
}

void SoilModel::takeSectionSnapshots(std::vector<SectionSnapshot>& out) {
  for (auto& s : section_snaps_) {
    if (spread()) sumToRoot(s);
    out.push_back(std::move(s));
  }
  section_snaps_.clear();
}

}  // namespace railvib::soil
