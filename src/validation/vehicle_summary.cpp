#include "vehicle_summary.hpp"

#include <cmath>
#include <limits>

namespace railvib::validation {

VehicleModeSummary summarise(const vehicle::VehicleModel& model, const std::vector<vehicle::Mode>& modes) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  VehicleModeSummary s{nan, nan, nan, nan, nan, nan};
  const vehicle::BodyInfo* bogie = nullptr;
  for (const auto& b : model.bodies()) {
    if (b.kind == vehicle::BodyKind::Bogie && b.name == "leading_bogie") bogie = &b;
  }
  for (const auto& m : modes) {
    if (m.name == "car-body bounce" && std::isnan(s.carbody_bounce_hz)) s.carbody_bounce_hz = m.frequency_hz;
    if (m.name == "axle hop (motor wheels, leading bogie)" && std::isnan(s.motor_hop_hz))
      s.motor_hop_hz = m.frequency_hz;
  }
  if (!bogie) return s;
  const double a = bogie->half_wheelbase_m;
  // the leading bogie's modes, lowest first (the list is sorted by frequency)
  const vehicle::Mode* first = nullptr;
  for (const auto& m : modes) {
    if (m.name.rfind("leading bogie", 0) != 0) continue;
    if (!first) {
      first = &m;
      continue;
    }
    // the flexible track splits the lowest mode into neighbours: keep the one the bogie owns most
    if (m.frequency_hz < 1.6 * first->frequency_hz &&
        m.name_share * m.vehicle_energy_share > first->name_share * first->vehicle_energy_share) {
      first = &m;
    }
    if (m.frequency_hz >= 1.6 * first->frequency_hz) break;
  }
  if (first) {
    s.bogie_first_hz = first->frequency_hz;
    s.bogie_first_pivot_m = std::isfinite(first->pivot_offset_m) ? first->pivot_offset_m : nan;
    s.bogie_first_pivot_to_axle_m =
        std::isfinite(first->pivot_offset_m) ? std::abs(std::abs(first->pivot_offset_m) - a) : nan;
  }
  for (const auto& m : modes) {
    if (m.name.rfind("leading bogie", 0) != 0 || !std::isfinite(m.pivot_offset_m)) continue;
    if (std::abs(m.pivot_offset_m) <= 0.5 * a) {
      s.bogie_pitch_hz = m.frequency_hz;
      break;
    }
  }
  return s;
}

}  // namespace railvib::validation
