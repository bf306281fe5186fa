#include "railvib/track/track_stepper.hpp"

#include <stdexcept>

namespace railvib::track {

namespace {
// The chain's track: one rail whose ballast forces the soil receives twice.
const TrackParams& halfTrack(const TrackParams& params, const char* who) {
  if (params.width != TrackWidth::Half) {
    throw ConfigError(std::string("track.width = full: ") + who +
                      " takes the half track only so far (the full width is in the track model and railvib_tool "
                      "receptance --load); set track.width: half");
  }
  return params;
}
}  // namespace

TrackStepper::TrackStepper(const TrackParams& params, double dt_s)
    : model_(halfTrack(params, "the track's time stepping (ballast loads for the soil)")), newmark_(model_, dt_s) {
  updateOutputs();
}

void TrackStepper::start(const std::vector<PointLoad>& initial_loads, double t0_s, double convection_speed_m_s) {
  buffer_.clear();
  for (const auto& l : initial_loads) {
    if (l.x_m >= model_.railStart() && l.x_m <= model_.railEnd()) buffer_.push_back(l);
  }
  newmark_.setConvectedStaticState(buffer_, convection_speed_m_s, t0_s);
  updateOutputs();
}

void TrackStepper::step(const std::vector<PointLoad>& loads) {
  buffer_.clear();
  for (const auto& l : loads) {
    if (l.x_m >= model_.railStart() && l.x_m <= model_.railEnd()) {
      buffer_.push_back(l);
    } else {
      ++ignored_;
    }
  }
  newmark_.step(buffer_);
  updateOutputs();
}

void TrackStepper::updateOutputs() {
  newmark_.ballastForces(ballast_);
  soil_.resize(ballast_.size());
  for (size_t i = 0; i < ballast_.size(); ++i) soil_[i] = kHalfTrackRailsOnSoil * ballast_[i];
}

std::vector<PointLoad> MovingLoadSource::loadsAt(double t_s) const {
  if (forces_n.size() != offsets_behind_m.size()) throw std::invalid_argument("MovingLoadSource: size mismatch");
  std::vector<PointLoad> out(forces_n.size());
  const double front = front_start_m + speed_m_s * t_s;
  for (size_t k = 0; k < forces_n.size(); ++k) out[k] = PointLoad{front - offsets_behind_m[k], forces_n[k]};
  return out;
}

}  // namespace railvib::track
