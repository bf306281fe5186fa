#include "railvib/track/track_stepper.hpp"

#include <stdexcept>

namespace railvib::track {

TrackStepper::TrackStepper(const TrackParams& params, double dt_s) : model_(params), newmark_(model_, dt_s) {
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
  newmark_.ballastForcesPerSeat(ballast_);
  soilLoadFrames(ballast_, static_cast<size_t>(model_.sleeperCount()), static_cast<size_t>(model_.railCount()), soil_);
}

std::vector<PointLoad> MovingLoadSource::loadsAt(double t_s) const {
  if (forces_n.size() != offsets_behind_m.size() || (!rails.empty() && rails.size() != forces_n.size()))
    throw std::invalid_argument("MovingLoadSource: size mismatch");
  std::vector<PointLoad> out(forces_n.size());
  const double front = front_start_m + speed_m_s * t_s;
  for (size_t k = 0; k < forces_n.size(); ++k)
    out[k] = PointLoad{front - offsets_behind_m[k], forces_n[k], rails.empty() ? Rail::Left : rails[k]};
  return out;
}

}  // namespace railvib::track
