#include <cmath>
#include <optional>
#include <sstream>

#include "railvib/track/track_model.hpp"

namespace railvib::track {

std::string foundationName(FoundationModel model) {
  switch (model) {
    case FoundationModel::Clm:
      return "clm";
    case FoundationModel::Winkler:
      return "winkler";
    case FoundationModel::Rigid:
      return "rigid";
  }
  return "?";
}

namespace {

// Plausible bedding moduli (N/mm^3). Under-sleeper pads: EN 16730 measures 0.05-0.5 N/mm^3 in use
// ("very soft" to "stiff"); under-ballast mats: DIN 45673-5 mats span ~0.01-0.2 N/mm^3. The bounds
// leave a factor of ~2-5 either side; beyond them the layer is no resilient layer (or no longer
// carries the track).
constexpr Range kUnderSleeperPadModulus{0.01, 2.0, false, false};
constexpr Range kUnderBallastMatModulus{0.002, 1.0, false, false};

std::optional<ResilientLayer> loadResilientLayer(const ConfigNode& track, const std::string& key,
                                                 const Range& modulus_n_mm3, double max_area_m2,
                                                 const std::string& max_area_reason) {
  if (!track.has(key)) return std::nullopt;
  const ConfigNode layer = track.section(key);
  const bool enabled = layer.flag("enabled", true);
  ResilientLayer l;
  l.bedding_modulus_n_mm3 = layer.number("bedding_modulus_n_mm3", modulus_n_mm3);
  l.bearing_area_m2 = layer.number("bearing_area_per_rail_seat_m2", Range{0.0, 20.0, true, false});
  if (l.bearing_area_m2 > max_area_m2 * (1.0 + 1e-9)) {
    std::ostringstream why;
    why << "at most " << max_area_m2 << " m^2 per rail seat: " << max_area_reason;
    layer.fail("bearing_area_per_rail_seat_m2", why.str());
  }
  // elastomers and bonded granulates: eta ~0.05-0.3; above 1 no solid layer is meant
  l.loss_factor = layer.number("loss_factor", Range{0.0, 1.0, false, false});
  l.reference_frequency_hz = layer.number("reference_frequency_hz", Range{1.0, 1000.0, false, false});
  // a disabled layer's values are validated all the same: switching it on cannot meet a bad one
  if (!enabled) return std::nullopt;
  return l;
}

}  // namespace

TrackParams loadTrackParams(const ConfigNode& root) {
  const ConfigNode track = root.section("track");
  TrackParams p;
  p.layout = loadTrackLayout(root);
  const ConfigNode rail = track.section("rail");
  p.rail_bending_stiffness_n_m2 = rail.number("bending_stiffness_n_m2", Range::open(1.0e3, 1.0e9));
  p.rail_mass_per_length_kg_m = rail.number("mass_per_length_kg_m", Range::open(1.0, 1000.0));
  p.elements_per_bay = static_cast<int>(rail.integer("elements_per_bay", 1, 64));

  const ConfigNode sleeper = track.section("sleeper");
  p.sleeper_mass_kg = sleeper.number("mass_kg", Range::open(0.0, 1.0e4));
  p.width = track.choice("width", {"half", "full"}) == "full" ? TrackWidth::Full : TrackWidth::Half;
  // Read whatever the width, so that a bad value is refused before a switch to full.
  p.sleeper_roll_inertia_kg_m2 = sleeper.number("roll_inertia_kg_m2", Range::open(0.0, 1.0e5));
  if (p.width == TrackWidth::Full) {
    if (!root.has("site")) track.fail("width", "full needs the rail gauge (site.rail_gauge_m): no site section");
    // the rail seats under the rails' centre lines
    p.rail_seat_offset_m = loadSiteLayout(root).exterior_rail_y_m;
    if (p.rail_seat_offset_m >= 0.5 * p.layout.length_m) {
      sleeper.fail("length_m", "the rail seats (+-" + std::to_string(p.rail_seat_offset_m) +
                                   " m, site.rail_gauge_m / 2) must lie on the sleeper");
    }
  }

  const ConfigNode pad = track.section("railpad");
  p.railpad_stiffness_n_m = pad.number("stiffness_n_m", Range::open(0.0, 1.0e12));
  p.railpad_damping_n_s_m = pad.number("damping_n_s_m", Range{0.0, 1.0e9, false, true});
  const ConfigNode ballast = track.section("ballast");
  p.ballast_stiffness_n_m = ballast.number("stiffness_n_m", Range::open(0.0, 1.0e12));
  p.ballast_damping_n_s_m = ballast.number("damping_n_s_m", Range{0.0, 1.0e9, false, true});

  // Resilient layers (optional): absent or `enabled: false` = none (the paper's track; the values
  // of a disabled layer are still validated, so that switching it on cannot meet a bad one).
  // the pad lies under the sleeper: it bears at most on the sleeper's bottom per rail seat
  const double sleeper_seat_m2 = 0.5 * p.layout.length_m * p.layout.width_m;
  p.under_sleeper_pad = loadResilientLayer(track, "under_sleeper_pad", kUnderSleeperPadModulus, sleeper_seat_m2,
                                           "half the sleeper's bottom (track.sleeper.length_m x width_m / 2)");
  p.under_ballast_mat = loadResilientLayer(track, "under_ballast_mat", kUnderBallastMatModulus, 20.0, "");

  const ConfigNode foundation = track.section("foundation");
  const std::string model = foundation.choice("model", {"clm", "winkler", "rigid"});
  // Both parameter sets are validated when present, the chosen one and the one kept for a switch
  // (foundation:=winkler): a bad value is refused whichever model runs.
  if (model == "clm" || foundation.has("clm")) {
    const ConfigNode clm = foundation.section("clm");
    p.clm.mass_kg = clm.number("mass_kg", Range::open(0.0, 1.0e7));
    p.clm.stiffness_n_m = clm.number("stiffness_n_m", Range::open(0.0, 1.0e12));
    p.clm.damping_n_s_m = clm.number("damping_n_s_m", Range{0.0, 1.0e10, false, true});
    p.clm.coupling_stiffness_n_m = clm.number("coupling_stiffness_n_m", Range{0.0, 1.0e12, false, true});
    // Negative on purpose (propagation delay [paper]); bounded so that the
    // foundation damping matrix stays positive semi-definite: d_f + 4 d_c >= 0
    // is the exact bound for the chain d_f I + d_c * Laplacian.
    p.clm.coupling_damping_n_s_m = clm.number("coupling_damping_n_s_m", Range::open(-1.0e10, 1.0e10));
    if (p.clm.damping_n_s_m + 4.0 * std::min(0.0, p.clm.coupling_damping_n_s_m) < 0.0) {
      std::ostringstream why;
      why << "negative coupling damping too large: d_f + 4 d_c must be >= 0 (d_f = " << p.clm.damping_n_s_m
          << "), otherwise the foundation chain is active (energy-producing)";
      clm.fail("coupling_damping_n_s_m", why.str());
    }
  }
  if (model == "winkler" || foundation.has("winkler")) {
    const ConfigNode w = foundation.section("winkler");
    const double ratio = w.number("ballast_to_foundation_stiffness_ratio", Range::open(0.0, 1.0e3));
    p.winkler.stiffness_n_m = p.ballast_stiffness_n_m / ratio;
    p.winkler.damping_n_s_m = w.number("damping_n_s_m", Range{0.0, 1.0e10, false, true});
  }
  p.foundation = model == "clm"       ? FoundationModel::Clm
                 : model == "winkler" ? FoundationModel::Winkler
                                      : FoundationModel::Rigid;

  {
    const ConfigNode ends = track.section("ends");
    p.ends.absorbing_length_m = p.layout.end_layer_m;  // read with the extent (loadTrackLayout)
    p.ends.max_damping_rate_1_s = ends.number("max_damping_rate_1_s", Range{0.0, 1.0e6, false, true});
  }

  // Consistency: number of sleepers and room for the end layers.
  const TrackLayout& layout = p.layout;
  const ConfigNode extent = track.section("extent");
  const long count = layout.sleeperCount();
  if (count < TrackParams::kMinSleepers) {
    std::ostringstream why;
    why << "the extent [" << layout.x_min_m << ", " << layout.x_max_m << "] m holds " << std::max(0L, count)
        << " sleepers at spacing " << layout.spacing_m << " m; at least " << TrackParams::kMinSleepers << " are needed";
    extent.fail("x_max_m", why.str());
  }
  if (count > 200000) extent.fail("x_max_m", "track too long (more than 200000 sleepers)");
  if (2.0 * p.ends.absorbing_length_m >= 0.8 * (layout.x_max_m - layout.x_min_m)) {
    track.section("ends").fail("absorbing_length_m",
                               "the two end layers would cover more than 80 % of the track extent");
  }

  const ConfigNode output = track.section("output");
  p.load_sample_rate_hz = output.number("load_sample_rate_hz", Range::open(0.0, 1.0e7));
  return p;
}

}  // namespace railvib::track
