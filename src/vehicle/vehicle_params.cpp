#include "railvib/vehicle/vehicle_params.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "railvib/common/site.hpp"
#include "railvib/common/stream_contract.hpp"

namespace railvib::vehicle {

namespace {
std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

VehicleParams loadVehicleParams(const ConfigNode& root) {
  const ConfigNode v = root.section("vehicle");
  VehicleParams p;
  const Range pos = Range::positive();
  const Range nonneg = Range::nonNegative();

  const ConfigNode car = v.section("carbody");
  p.end_carbody_mass_kg = car.number("end_mass_kg", pos);
  p.central_carbody_mass_kg = car.number("central_mass_kg", pos);
  p.end_carbody_pitch_inertia_kg_m2 = car.number("end_pitch_inertia_kg_m2", pos);
  p.central_carbody_pitch_inertia_kg_m2 = car.number("central_pitch_inertia_kg_m2", pos);

  const ConfigNode bogie = v.section("bogie");
  p.bogie_mass_kg = bogie.number("mass_kg", pos);
  p.bogie_pitch_inertia_kg_m2 = bogie.number("pitch_inertia_kg_m2", pos);

  const ConfigNode mw = v.section("motor_wheel");
  p.motor_mass_kg = mw.number("mass_kg", pos);
  p.tread_mass_kg = mw.number("tread_mass_kg", pos);
  p.ring_stiffness_n_m = mw.number("ring_stiffness_n_m", pos);
  p.ring_damping_n_s_m = mw.number("ring_damping_n_s_m", nonneg);
  p.motor_radius_m = mw.number("radius_m", Range::closed(0.1, 1.0));

  const ConfigNode tw = v.section("trailer_wheel");
  p.trailer_mass_kg = tw.number("mass_kg", pos);
  p.trailer_radius_m = tw.number("radius_m", Range::closed(0.1, 1.0));

  const ConfigNode prim = v.section("primary_suspension");
  p.motor_primary_stiffness_n_m = prim.number("motor_stiffness_n_m", pos);
  p.motor_primary_damping_n_s_m = prim.number("motor_damping_n_s_m", nonneg);
  p.trailer_primary_stiffness_n_m = prim.number("trailer_stiffness_n_m", pos);
  p.trailer_primary_damping_n_s_m = prim.number("trailer_damping_n_s_m", nonneg);

  const ConfigNode sec = v.section("secondary_suspension");
  p.secondary_stiffness_n_m = sec.number("stiffness_n_m", pos);
  p.secondary_damping_n_s_m = sec.number("damping_n_s_m", nonneg);

  p.axle_offsets_m = v.numbers("axle_offsets_m", Range::closed(0.0, 100.0), 6, 6);
  if (p.axle_offsets_m.front() != 0.0) v.fail("axle_offsets_m", "the first offset is the front axle and must be 0");
  for (size_t i = 1; i < p.axle_offsets_m.size(); ++i) {
    if (!(p.axle_offsets_m[i] > p.axle_offsets_m[i - 1])) {
      v.fail("axle_offsets_m", "axle offsets must be strictly increasing (front to rear); offset " + std::to_string(i) +
                                   " = " + fmt(p.axle_offsets_m[i]) + " m is not behind offset " +
                                   std::to_string(i - 1) + " = " + fmt(p.axle_offsets_m[i - 1]) + " m");
    }
  }
  const std::vector<std::string> types = v.texts("axle_types");
  if (types.size() != p.axle_offsets_m.size()) {
    v.fail("axle_types", "needs one type per axle (" + std::to_string(p.axle_offsets_m.size()) + "), got " +
                             std::to_string(types.size()));
  }
  p.axle_types.clear();
  for (const auto& t : types) {
    if (t == "motor") {
      p.axle_types.push_back(AxleType::Motor);
    } else if (t == "trailer") {
      p.axle_types.push_back(AxleType::Trailer);
    } else {
      v.fail("axle_types", "unknown axle type '" + t + "' (allowed: motor, trailer)");
    }
  }
  p.hertz_constant_n_m1_5 = v.section("contact").number("hertz_constant_n_m1_5", pos);

  const ConfigNode half = v.section("half_vehicle");
  // 1 = the whole vehicle on one rail (a sensitivity study), 0.5 = the symmetric half.
  p.body_share_per_rail = half.number("body_share_per_rail", Range{0.0, 1.0, true, false});

  const ConfigNode geo = v.section("geometry");
  p.carbody_com_offsets_m = geo.numbers("carbody_com_offsets_m", Range::any(), 3, 3);
  p.articulation_offsets_m = geo.numbers("articulation_offsets_m", Range::any(), 2, 2);
  const double b0 = 0.5 * (p.axle_offsets_m[0] + p.axle_offsets_m[1]);
  const double b1 = 0.5 * (p.axle_offsets_m[2] + p.axle_offsets_m[3]);
  const double b2 = 0.5 * (p.axle_offsets_m[4] + p.axle_offsets_m[5]);
  const auto& a = p.articulation_offsets_m;
  const auto& c = p.carbody_com_offsets_m;
  if (!(b0 < a[0] && a[0] < b1 && b1 < a[1] && a[1] < b2)) {
    geo.fail("articulation_offsets_m", "articulations must lie between the bogie centres (" + fmt(b0) + ", " + fmt(b1) +
                                           ", " + fmt(b2) + " m behind the front axle)");
  }
  if (!(c[0] < a[0] && a[0] < c[1] && c[1] < a[1] && a[1] < c[2])) {
    geo.fail("carbody_com_offsets_m", "each carbody centre must lie inside its section (articulations at " + fmt(a[0]) +
                                          " and " + fmt(a[1]) + " m)");
  }
  const ConfigNode art = v.section("articulation");
  art.choice("model", {"vertical_pin"});
  p.articulation_pitch_stiffness_n_m_rad = art.number("pitch_stiffness_n_m_rad", nonneg);
  p.articulation_pitch_damping_n_m_s_rad = art.number("pitch_damping_n_m_s_rad", nonneg);
  p.gravity_m_s2 = v.number("gravity_m_s2", Range::closed(9.0, 10.0), 9.81);
  return p;
}

UnevennessParams loadUnevennessParams(const ConfigNode& root) {
  UnevennessParams u;
  const ConfigNode un = root.section("unevenness");
  const ConfigNode d = un.section("defect");
  u.defect.enabled = d.flag("enabled");
  u.defect.position_m = d.number("position_m", Range::open(-1.0e5, 1.0e5));
  u.defect.height_m = d.number("height_m", Range::closed(0.0, 0.05));
  u.defect.length_m = d.number("length_m", Range::closed(0.0, 1.0));
  if (u.defect.enabled && root.has("track")) {
    const TrackLayout track = loadTrackLayout(root);
    const double x0 = track.x_min_m;
    const double x1 = track.x_max_m;
    if (u.defect.position_m < x0 || u.defect.position_m + u.defect.length_m > x1) {
      d.fail("position_m", "the defect [" + fmt(u.defect.position_m) + ", " +
                               fmt(u.defect.position_m + u.defect.length_m) + "] m lies outside the modelled track [" +
                               fmt(x0) + ", " + fmt(x1) + "] m (track.extent)");
    }
  }
  if (un.has("random")) {
    const ConfigNode r = un.section("random");
    auto& p = u.random;
    p.enabled = r.flag("enabled");
    p.psd = r.choice("psd", {"fra", "power_law"}, "fra");
    p.fra_a_m2_rad_m = r.number("fra_a_m2_rad_m", Range::positive(), p.fra_a_m2_rad_m);
    p.fra_cutoff_rad_m = r.number("fra_cutoff_rad_m", Range::positive(), p.fra_cutoff_rad_m);
    p.fra_k = r.number("fra_k", Range::positive(), p.fra_k);
    p.power_law_a_m3_rad = r.number("power_law_a_m3_rad", Range::positive(), p.power_law_a_m3_rad);
    p.power_law_ref_rad_m = r.number("power_law_ref_rad_m", Range::positive(), p.power_law_ref_rad_m);
    p.power_law_exponent = r.number("power_law_exponent", Range::closed(0.0, 6.0), p.power_law_exponent);
    p.min_wavelength_m = r.number("min_wavelength_m", Range::positive(), p.min_wavelength_m);
    p.max_wavelength_m = r.number("max_wavelength_m", Range::positive(), p.max_wavelength_m);
    if (p.max_wavelength_m <= p.min_wavelength_m) r.fail("max_wavelength_m", "must exceed min_wavelength_m");
    p.component_count = static_cast<int>(r.integer("component_count", 1, 100000, p.component_count));
    p.seed = static_cast<unsigned long>(r.integer("seed", 0, 2147483647L, static_cast<long>(p.seed)));
    p.grid_spacing_m = r.number("grid_spacing_m", Range::closed(1e-4, 0.1), p.grid_spacing_m);
  }
  if (un.has("measured_profile")) {
    const ConfigNode m = un.section("measured_profile");
    u.measured.enabled = m.flag("enabled");
    if (u.measured.enabled) {
      u.measured.file = m.filePath("file");
      std::error_code ec;
      if (!std::filesystem::is_regular_file(u.measured.file, ec)) {
        m.fail("file", "no such file: " + u.measured.file + " (a path is relative to the file that sets it)");
      }
    } else if (m.has("file")) {
      m.text("file");  // kept for when the profile is enabled again: still a file name
    }
    u.measured.scale = m.number("scale", Range::closed(-1.0e3, 1.0e3), 1.0);
    u.measured.max_abs_m = loadStreamLimits(root).unevenness_m;
  }
  return u;
}

PassageParams loadPassageParams(const ConfigNode& root) {
  const ConfigNode s = root.section("simulation");
  PassageParams p;
  p.vehicle_track = s.choice("vehicle_track", {"flexible", "rigid"}, "flexible") == "rigid" ? VehicleTrack::Rigid
                                                                                            : VehicleTrack::Flexible;
  p.speed_m_s = s.number("speed_m_s", Range::open(0.0, 100.0));
  p.duration_s = s.number("duration_s", Range::open(0.0, 600.0));
  // Newmark beta=1/4 is unconditionally stable; accuracy limits dt: the
  // stiffest vehicle mode (tread on the Hertz spring, ~600 Hz) needs >= 20
  // steps per period and the defect (~7 ms at 30 km/h) >= 100 steps.
  p.time_step_s = s.number("time_step_s", Range::closed(1.0e-7, 5.0e-5));
  p.front_axle_start_m = s.number("front_axle_start_m", Range::open(-1.0e5, 1.0e5));
  p.contact_tolerance = s.number("contact_tolerance", Range::closed(1e-14, 1e-4), p.contact_tolerance);
  p.convected_track_start = s.flag("convected_track_start", false);
  return p;
}

}  // namespace railvib::vehicle
