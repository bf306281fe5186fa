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
  newmark_.ballastForces(ballast_);
  soil_.resize(ballast_.size());
  for (size_t i = 0; i < ballast_.size(); ++i) soil_[i] = 2.0 * ballast_[i];
}

std::vector<PointLoad> MovingLoadSource::loadsAt(double t_s) const {
  if (forces_n.size() != offsets_behind_m.size()) throw std::invalid_argument("MovingLoadSource: size mismatch");
  std::vector<PointLoad> out(forces_n.size());
  const double front = front_start_m + speed_m_s * t_s;
  for (size_t k = 0; k < forces_n.size(); ++k) out[k] = PointLoad{front - offsets_behind_m[k], forces_n[k]};
  return out;
}

std::vector<double> staticWheelLoadsPerRail(const ConfigNode& vehicle, double g_m_s2) {
  const ConfigNode carbody = vehicle.section("carbody");
  const ConfigNode bogie = vehicle.section("bogie");
  const ConfigNode motor = vehicle.section("motor_wheel");
  const ConfigNode trailer = vehicle.section("trailer_wheel");
  const std::vector<std::string> types = vehicle.texts("axle_types");
  const std::vector<double> offsets = vehicle.numbers("axle_offsets_m", Range::nonNegative(), 1, 64);
  if (types.size() != offsets.size()) vehicle.fail("axle_types", "must have one entry per axle_offsets_m entry");
  const size_t axles = offsets.size();
  if (axles % 2 != 0) vehicle.fail("axle_offsets_m", "expected two axles per bogie");
  double total = 2.0 * carbody.number("end_mass_kg", Range::positive()) +
                 carbody.number("central_mass_kg", Range::positive()) +
                 static_cast<double>(axles / 2) * bogie.number("mass_kg", Range::positive());
  const double motor_wheel =
      motor.number("mass_kg", Range::positive()) + motor.number("tread_mass_kg", Range::nonNegative());
  const double trailer_wheel = trailer.number("mass_kg", Range::positive());
  for (const auto& t : types) {
    if (t == "motor") {
      total += 2.0 * motor_wheel;
    } else if (t == "trailer") {
      total += 2.0 * trailer_wheel;
    } else {
      vehicle.fail("axle_types", "each entry must be motor or trailer, got '" + t + "'");
    }
  }
  // Uniform split over the axles, per rail (half of an axle load).
  return std::vector<double>(axles, total * g_m_s2 / (2.0 * static_cast<double>(axles)));
}

}  // namespace railvib::track
