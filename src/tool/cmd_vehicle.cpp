// railvib_tool vehicle commands: vehicle-modes, wheel-impedance, passage.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

#include "command_registry.hpp"
#include "railvib/io/atomic_file.hpp"
#include "railvib/io/csv.hpp"
#include "railvib/signal/decimator.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/modal.hpp"
#include "railvib/vehicle/passage.hpp"
#include "railvib/vehicle/resilient_wheel.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using nlohmann::json;
using namespace railvib::vehicle;

/// --vehicle NAME: the library entry to run instead of vehicle.name.
void addVehicleOption(ArgParser& p) {
  p.option("vehicle", "vehicle of the library `vehicles` (default: vehicle.name)", "");
}
void vehicleOverride(const ArgParser& p, std::vector<std::string>& extra) {
  if (p.has("vehicle") && !p.get("vehicle").empty()) extra.push_back("vehicle.name=" + p.get("vehicle"));
}

/// The resilient-wheels measure applied to the vehicle (vehicle_params.hpp), for the JSON; a vehicle
/// without it prints nothing (its output as it was).
void addResilientWheels(const VehicleParams& v, json& out) {
  if (!v.resilient_wheels) return;
  const ResilientWheelParams& r = *v.resilient_wheels;
  out["resilient_wheels"] = {{"wheels", r.wheels == ResilientWheelSet::Rigid       ? "rigid"
                                        : r.wheels == ResilientWheelSet::Resilient ? "resilient"
                                                                                   : "all"},
                             {"tread_mass_kg", r.tread_mass_kg},
                             {"stiffness_n_m", r.stiffness_n_m},
                             {"damping_n_s_m", r.damping_n_s_m}};
}

std::string trackChoice(const ArgParser& p) {
  const std::string t = p.get("track");
  if (t != "rigid" && t != "flexible") throw ArgError("--track must be rigid or flexible, got '" + t + "'");
  return t;
}

json modesJson(const std::vector<Mode>& modes, bool flexible, bool full_width) {
  json arr = json::array();
  for (const auto& m : modes) {
    json j = {{"name", m.name},
              {"body", m.body},
              {"f0_hz", m.frequency_hz},
              {"damping_ratio", m.damping_ratio},
              {"name_energy_share", m.name_share}};
    if (flexible) j["vehicle_energy_share"] = m.vehicle_energy_share;
    if (full_width) j["antisymmetric_energy_share"] = m.antisymmetric_share;
    if (std::isfinite(m.pivot_offset_m)) j["pivot_behind_bogie_centre_m"] = m.pivot_offset_m;
    arr.push_back(j);
  }
  return arr;
}

int vehicleModes(const std::vector<std::string>& args) {
  ArgParser p("vehicle-modes", "eigenanalysis of the vehicle linearised about static equilibrium");
  addConfigOptions(p);
  addVehicleOption(p);
  p.option("track", "rigid | flexible", "rigid");
  p.option("foundation", "flexible track foundation: clm | winkler (default: config)", "");
  p.option("min-vehicle-share", "flexible: keep modes with at least this share of kinetic energy in the vehicle",
           "0.3");
  p.option("margin", "flexible: local track length beyond the end axles (m)", "6");
  if (!p.parse(args)) return 0;
  const std::string track = trackChoice(p);
  std::vector<std::string> extra;
  if (p.has("foundation") && !p.get("foundation").empty())
    extra.push_back("track.foundation.model=" + p.get("foundation"));
  vehicleOverride(p, extra);
  const Config cfg = loadConfig(p, extra);
  const auto t0 = std::chrono::steady_clock::now();
  const VehicleModel model(loadVehicleParams(cfg.root()));
  std::vector<Mode> modes;
  if (track == "rigid") {
    modes = vehicleModesRigid(model);
  } else {
    const auto tp = track::loadTrackParams(cfg.root());
    ModalOptions mo;
    mo.min_vehicle_energy_share = p.getDouble("min-vehicle-share", 0.0, 1.0);
    mo.margin_m = p.getDouble("margin", 0.0, 1e3);
    modes = vehicleModesFlexible(model, tp, mo);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  json out = {{"vehicle", model.params().name},
              {"track", track},
              {"dof", model.dofCount()},
              {"wall_time_s", wall},
              {"modes", modesJson(modes, track == "flexible", model.fullWidth())}};
  if (model.fullWidth()) out["width"] = "full";  // the half vehicle's output as it was
  addResilientWheels(model.params(), out);
  if (track == "rigid") {
    out["linearised_hertz_stiffness_n_m"] = linearisedHertzStiffness(model);
  }
  printJson(out);
  return 0;
}

int wheelImpedance(const std::vector<std::string>& args) {
  ArgParser p("wheel-impedance", "direct impedance F/v at a wheel's contact body, frequency domain");
  addConfigOptions(p);
  addVehicleOption(p);
  p.option("wheel",
           "wheel (axle) index, front to rear (T2000: 0 leading bogie motor wheel, 2 middle bogie motor wheel)", "0");
  p.option("rail", "track.width full: the wheel's rail, left | right", "left");
  p.option("load",
           "track.width full: one (the wheel alone) | both (both wheels of its axle in phase: the half vehicle's "
           "case) | anti (in anti-phase)",
           "one");
  p.option("track", "rigid | flexible", "rigid");
  p.option("csv", "output CSV (f_hz, |Z| N s/m, phase deg, Re, Im)");
  p.option("f-min", "lowest frequency (Hz)", "1");
  p.option("f-max", "highest frequency (Hz)", "200");
  p.option("points", "log-spaced frequencies", "300");
  p.option("closed-form",
           "a resilient wheel (its tread on a ring under a hub on one element), rigid track, half width: compare "
           "with the chain's closed form, the body above the hub blocked | free-mass (docs/vehicle.md, "
           "\"Resilient wheels\"; CSV gains abs_z_closed_form_n_s_m and rel_dev)",
           "");
  if (!p.parse(args)) return 0;
  const std::string track = trackChoice(p);
  const std::string closed_form = p.has("closed-form") ? p.get("closed-form") : "";
  if (!closed_form.empty() && closed_form != "blocked" && closed_form != "free-mass")
    throw ArgError("--closed-form must be blocked or free-mass, got '" + closed_form + "'");
  if (!closed_form.empty() && track != "rigid") throw ArgError("--closed-form compares on the rigid track");
  std::vector<std::string> extra;
  vehicleOverride(p, extra);
  const Config cfg = loadConfig(p, extra);
  const VehicleModel model(loadVehicleParams(cfg.root()));
  const int axle = static_cast<int>(p.getInt("wheel", 0, 1000));
  if (axle < 0 || axle >= model.axleCount())
    throw ArgError("--wheel must be in 0.." + std::to_string(model.axleCount() - 1));
  const std::string rail_name = p.get("rail"), load_name = p.get("load");
  if (rail_name != "left" && rail_name != "right") throw ArgError("--rail must be left or right");
  if (load_name != "one" && load_name != "both" && load_name != "anti")
    throw ArgError("--load must be one, both or anti");
  if (!model.fullWidth() && (rail_name != "left" || load_name != "one"))
    throw ArgError("--rail and --load need the full-width vehicle (--set track.width=full)");
  const int wheel = model.wheelIndex(axle, rail_name == "left" ? track::Rail::Left : track::Rail::Right);
  const AxleLoading loading = load_name == "both"   ? AxleLoading::InPhase
                              : load_name == "anti" ? AxleLoading::AntiPhase
                                                    : AxleLoading::OneWheel;
  const double f0 = p.getDouble("f-min", 1e-3, 1e5), f1 = p.getDouble("f-max", 1e-3, 1e5);
  const long n = p.getInt("points", 2, 1000000);
  if (!(f0 > 0.0 && f1 > f0 && n >= 2)) throw ArgError("need 0 < --f-min < --f-max and --points >= 2");
  std::vector<double> f(static_cast<size_t>(n));
  for (long k = 0; k < n; ++k) f[static_cast<size_t>(k)] = f0 * std::pow(f1 / f0, static_cast<double>(k) / (n - 1));
  const auto t0 = std::chrono::steady_clock::now();
  const auto Z = track == "rigid"
                     ? wheelImpedanceRigid(model, wheel, f, loading)
                     : wheelImpedanceFlexible(model, track::loadTrackParams(cfg.root()), wheel, f, 0.0, loading);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  size_t imin = 0;
  for (size_t k = 0; k < Z.size(); ++k) {
    if (std::abs(Z[k]) < std::abs(Z[imin])) imin = k;
  }
  // The resilient wheel's closed form (resilient_wheel.hpp): Z_c per frequency and |Z - Z_c| / |Z_c|.
  std::vector<std::complex<double>> Zc;
  json closed;
  if (!closed_form.empty()) {
    const auto chain = resilientWheelChain(model, wheel);
    if (!chain) {
      throw ArgError("--closed-form: wheel " + std::to_string(axle) +
                     " is no resilient wheel of the half vehicle (its contact body is not a tread on one ring under "
                     "a hub held by one element; resilient_wheels makes rigid wheels resilient)");
    }
    const ChainTop top = closed_form == "blocked" ? ChainTop::Blocked : ChainTop::FreeMass;
    double max_dev = 0.0, f_within = f.front();
    for (size_t k = 0; k < f.size(); ++k) {
      Zc.push_back(resilientWheelImpedance(*chain, f[k], top));
      const double dev = std::abs(Z[k] - Zc[k]) / std::abs(Zc[k]);
      max_dev = std::max(max_dev, dev);
      if (dev > 0.01) f_within = k + 1 < f.size() ? f[k + 1] : std::nan("");
    }
    const std::vector<double> fc = resilientWheelFrequencies(*chain, top);
    // the model's tread mode: the rigid-track mode of this tread nearest the closed form's ring resonance
    double f_model = std::nan(""), zeta_model = std::nan("");
    for (const Mode& m : vehicleModesRigid(model)) {
      if (m.body != chain->tread) continue;
      if (!std::isfinite(f_model) || std::abs(m.frequency_hz - fc.back()) < std::abs(f_model - fc.back())) {
        f_model = m.frequency_hz;
        zeta_model = m.damping_ratio;
      }
    }
    closed = {{"top", closed_form},
              {"tread", chain->tread},
              {"hub", chain->hub},
              {"upper", chain->upper},
              {"tread_mass_kg", chain->tread_mass_kg},
              {"hub_mass_kg", chain->hub_mass_kg},
              {"upper_mass_kg", chain->upper_mass_kg},
              {"ring_stiffness_n_m", chain->ring_stiffness_n_m},
              {"ring_damping_n_s_m", chain->ring_damping_n_s_m},
              {"primary_stiffness_n_m", chain->primary_stiffness_n_m},
              {"primary_damping_n_s_m", chain->primary_damping_n_s_m},
              {"hertz_stiffness_n_m", chain->hertz_stiffness_n_m},
              {"max_rel_dev", max_dev},
              {"within_1_percent_from_hz", f_within},
              {"natural_frequencies_hz", fc},
              {"ring_resonance_hz", fc.back()},
              {"model_tread_mode_hz", f_model},
              {"model_tread_mode_damping_ratio", zeta_model},
              {"ring_resonance_rel_dev", (f_model - fc.back()) / fc.back()}};
  }
  if (p.has("csv") && !p.get("csv").empty()) {
    std::vector<std::string> columns{"f_hz", "abs_z_n_s_m", "phase_deg", "re_z_n_s_m", "im_z_n_s_m"};
    if (!Zc.empty()) {
      columns.push_back("abs_z_closed_form_n_s_m");
      columns.push_back("rel_dev");
    }
    io::CsvWriter csv(p.get("csv"), columns);
    for (size_t k = 0; k < Z.size(); ++k) {
      std::vector<double> row{f[k], std::abs(Z[k]), std::arg(Z[k]) * 180.0 / M_PI, Z[k].real(), Z[k].imag()};
      if (!Zc.empty()) {
        row.push_back(std::abs(Zc[k]));
        row.push_back(std::abs(Z[k] - Zc[k]) / std::abs(Zc[k]));
      }
      csv.row(row);
    }
    csv.commit();
  }
  json out = {{"vehicle", model.params().name},
              {"wheel", axle},
              {"axle_type", model.wheels()[wheel].type == AxleType::Motor ? "motor" : "trailer"},
              {"track", track},
              {"points", n},
              {"min_abs_z_n_s_m", std::abs(Z[imin])},
              {"f_at_min_abs_z_hz", f[imin]},
              {"csv", p.has("csv") ? p.get("csv") : ""},
              {"wall_time_s", wall}};
  if (model.fullWidth()) {  // the half vehicle's output as it was
    out["width"] = "full";
    out["rail"] = rail_name;
    out["load"] = load_name;
  }
  addResilientWheels(model.params(), out);
  if (!closed.is_null()) out["closed_form"] = closed;
  printJson(out);
  return 0;
}

// ---------------------------------------------------------------- passage
// The coupled run offline: its setup, the CSV outputs it streams, and its JSON summary.

struct PassageSetup {
  Config config;
  VehicleModel model;
  PassageParams passage;
  UnevennessParams unevenness_params;
  track::TrackParams track;
  Unevenness unevenness;

  explicit PassageSetup(Config cfg)
      : config(std::move(cfg)),
        model(loadVehicleParams(config.root())),
        passage(loadPassageParams(config.root())),
        unevenness_params(loadUnevennessParams(config.root())),
        track(track::loadTrackParams(config.root())),
        unevenness(unevenness_params, track.layout.x_min_m, track.layout.x_max_m) {}
  bool flexible() const { return passage.vehicle_track == VehicleTrack::Flexible; }
};

/// CSV outputs of a passage: contact forces and unevenness every N-th step, a column per wheel
/// (axleI_... at half width; axleI_left_... and axleI_right_... at full width); on a flexible track
/// the soil loads (half width: both rails, 2 x the half track's seat, a column x_<position> per sleeper;
/// full width: each rail seat's force, columns x_<position>_left and x_<position>_right per sleeper,
/// which `railvib_tool soil --loads` spreads over the footprint with their resultant at the seat;
/// anti-alias decimated to track.output.load_sample_rate_hz) and the sleepers.
class PassageCsv {
 public:
  PassageCsv(const std::string& dir, const PassageSetup& setup, const std::vector<double>& sleepers, long every)
      : model_(setup.model),
        nw_(setup.model.wheelCount()),
        ns_(sleepers.size()),
        seats_(setup.model.fullWidth() ? 2 : 1),
        every_(static_cast<uint64_t>(every)),
        forces_(dir + "/contact_forces.csv", wheelColumns("_force_n")),
        unevenness_(dir + "/unevenness.csv", wheelColumns("_unevenness_m")) {
    if (!setup.flexible()) return;
    std::vector<std::string> cols{"t_s"};
    // same header as `railvib_tool moving-load`: x_<sleeper position, 6 significant digits>
    for (size_t s = 0; s < ns_; ++s) {
      std::ostringstream name;
      name << "x_" << std::setprecision(6) << sleepers[s];
      if (seats_ == 1) {
        cols.push_back(name.str());
      } else {
        for (track::Rail rail : {track::Rail::Left, track::Rail::Right}) cols.push_back(railColumn(name.str(), rail));
      }
    }
    soil_ = std::make_unique<io::CsvWriter>(dir + "/soil_loads.csv", cols);
    signal::DecimatorSpec spec;
    spec.input_rate_hz = 1.0 / setup.passage.time_step_s;
    const double ratio = std::round(spec.input_rate_hz / setup.track.load_sample_rate_hz);
    spec.output_rate_hz = spec.input_rate_hz / std::max(1.0, ratio);
    decimator_ = std::make_unique<signal::Decimator>(spec, ns_ * seats_);
    io::CsvWriter sl(dir + "/sleepers.csv", {"sleeper", "x_m"});
    for (size_t s = 0; s < ns_; ++s) sl.row({static_cast<double>(s), sleepers[s]});
    sl.commit();
  }

  void write(const PassageBlock& block) {
    for (size_t k = 0; k < block.sampleCount(); ++k) {
      if ((block.first_index + k) % every_ != 0) continue;
      writeRow(forces_, block.time_s[k], block.contact_force_n, k);
      writeRow(unevenness_, block.time_s[k], block.unevenness_m, k);
    }
    if (!decimator_) return;
    if (static_cast<size_t>(block.rail_seat_count) != seats_) {
      throw std::logic_error("passage: a block with " + std::to_string(block.rail_seat_count) + " rail seats, " +
                             std::to_string(seats_) + " expected");
    }
    track::soilLoadFrames(block.ballast_force_n, ns_, seats_, soil_in_);
    soil_out_.clear();
    decimator_->push(soil_in_.data(), block.sampleCount(), soil_out_);
    writeSoil();
  }

  void commit() {
    if (decimator_) {
      soil_out_.clear();
      decimator_->flush(soil_out_);
      writeSoil();
      soil_->commit();
    }
    forces_.commit();
    unevenness_.commit();
  }

 private:
  std::vector<std::string> wheelColumns(const std::string& suffix) const {
    std::vector<std::string> cols{"t_s"};
    for (int i = 0; i < nw_; ++i) {
      const WheelInfo& w = model_.wheels()[i];
      if (!model_.fullWidth()) {
        cols.push_back("axle" + std::to_string(i) + suffix);
      } else {
        cols.push_back(railColumn("axle" + std::to_string(w.axle), w.rail) + suffix);
      }
    }
    return cols;
  }
  void writeRow(io::CsvWriter& csv, double t_s, const std::vector<double>& per_wheel, size_t k) {
    row_.assign(1, t_s);
    for (int i = 0; i < nw_; ++i) row_.push_back(per_wheel[k * nw_ + i]);
    csv.row(row_);
  }
  void writeSoil() {
    const size_t width = ns_ * seats_;
    for (size_t k = 0; k + width <= soil_out_.size(); k += width) {
      row_.assign(1, decimator_->outputTime(soil_rows_++));
      row_.insert(row_.end(), soil_out_.begin() + static_cast<long>(k),
                  soil_out_.begin() + static_cast<long>(k + width));
      soil_->row(row_);
    }
  }

  const VehicleModel& model_;
  int nw_;
  size_t ns_, seats_;
  uint64_t every_;
  io::CsvWriter forces_, unevenness_;
  std::unique_ptr<io::CsvWriter> soil_;
  std::unique_ptr<signal::Decimator> decimator_;
  std::vector<double> soil_in_, soil_out_, row_;
  uint64_t soil_rows_ = 0;
};

/// Peak and minimum contact force of each wheel over the run.
struct ContactForcePeaks {
  explicit ContactForcePeaks(int wheels) : peak(wheels, 0.0), time_of_peak(wheels, 0.0), min(wheels, 1e300) {}
  void add(const PassageBlock& block) {
    const size_t nw = peak.size();
    for (size_t k = 0; k < block.sampleCount(); ++k) {
      for (size_t i = 0; i < nw; ++i) {
        const double F = block.contact_force_n[k * nw + i];
        if (F > peak[i]) {
          peak[i] = F;
          time_of_peak[i] = block.time_s[k];
        }
        min[i] = std::min(min[i], F);
      }
    }
  }
  std::vector<double> peak, time_of_peak, min;
};

json passageWheels(const PassageSetup& setup, const VehiclePassage& run, const ContactForcePeaks& f) {
  const auto& s0 = run.initialState();
  const auto& defect = setup.unevenness_params.defect;
  json wheels = json::array();
  for (int i = 0; i < setup.model.wheelCount(); ++i) {
    const double x0 = setup.passage.front_axle_start_m - setup.model.wheels()[i].offset_m;
    const double t_defect =
        defect.enabled ? (defect.position_m + 0.5 * defect.length_m - x0) / setup.passage.speed_m_s : -1.0;
    const WheelInfo& w = setup.model.wheels()[i];
    json wheel = {{"axle", setup.model.fullWidth() ? w.axle : i}};
    if (setup.model.fullWidth()) wheel["rail"] = w.rail == track::Rail::Left ? "left" : "right";
    wheel.update({{"type", w.type == AxleType::Motor ? "motor" : "trailer"},
                  {"static_force_n", s0.contact_force_n[i]},
                  {"peak_force_n", f.peak[i]},
                  {"peak_dynamic_force_n", f.peak[i] - s0.contact_force_n[i]},
                  {"min_force_n", f.min[i]},
                  {"time_of_peak_s", f.time_of_peak[i]},
                  {"time_over_defect_s", t_defect}});
    wheels.push_back(wheel);
  }
  return wheels;
}

int passage(const std::vector<std::string>& args) {
  ArgParser p("passage", "coupled vehicle / track passage over the defect (contact forces, soil loads, summary)");
  addConfigOptions(p);
  addVehicleOption(p);
  p.option("out", "output directory");
  p.option("speed", "speed (m/s; default simulation.speed_m_s)", "");
  p.option("duration", "simulated time (s; default simulation.duration_s)", "");
  p.option("dt", "time step (s; default simulation.time_step_s)", "");
  p.option("foundation", "clm | winkler (default: config)", "");
  p.option("track", "rigid | flexible (default: simulation.vehicle_track)", "");
  p.option("csv-every", "write every N-th step to contact_forces.csv / unevenness.csv", "10");
  if (!p.parse(args)) return 0;
  if (!p.has("out") || p.get("out").empty()) throw ArgError("passage: --out DIR is required");
  std::vector<std::string> extra;
  if (p.has("speed")) extra.push_back("simulation.speed_m_s=" + p.get("speed"));
  if (p.has("duration")) extra.push_back("simulation.duration_s=" + p.get("duration"));
  if (p.has("dt")) extra.push_back("simulation.time_step_s=" + p.get("dt"));
  if (p.has("foundation")) extra.push_back("track.foundation.model=" + p.get("foundation"));
  if (p.has("track")) extra.push_back("simulation.vehicle_track=" + trackChoice(p));
  vehicleOverride(p, extra);
  const long every = p.getInt("csv-every", 1, 1000000000);
  if (every < 1) throw ArgError("--csv-every must be >= 1");
  const PassageSetup setup(loadConfig(p, extra));

  const auto t_start = std::chrono::steady_clock::now();
  PassageOptions opt;
  opt.record_ballast = setup.flexible();
  VehiclePassage run(setup.model, setup.unevenness, setup.passage, makeRailSupport(setup.passage, setup.track), opt);
  const double t_setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  const std::string dir = p.get("out");
  std::filesystem::create_directories(dir);
  PassageCsv csv(dir, setup, run.rail().sleeperPositions(), every);
  ContactForcePeaks forces(setup.model.wheelCount());
  PassageBlock block;
  const uint64_t total = run.totalSamples();
  auto last_print = std::chrono::steady_clock::now();
  while (!run.finished()) {
    run.advance(4096, block);
    forces.add(block);
    csv.write(block);
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_print).count() > 5.0) {
      last_print = now;
      const double frac = static_cast<double>(run.nextSampleIndex()) / static_cast<double>(total);
      const double el = std::chrono::duration<double>(now - t_start).count();
      std::cerr << "passage: " << static_cast<int>(100 * frac) << " %, t = " << run.time() << " s, ETA "
                << el * (1.0 - frac) / std::max(frac, 1e-9) << " s\n";
    }
  }
  csv.commit();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  json summary({{"vehicle", setup.model.params().name},
                {"track", setup.flexible() ? "flexible" : "rigid"},
                {"foundation", setup.flexible() ? track::foundationName(setup.track.foundation) : "none"},
                {"speed_m_s", setup.passage.speed_m_s},
                {"duration_s", setup.passage.duration_s},
                {"time_step_s", setup.passage.time_step_s},
                {"steps", total - 1},
                {"weight_per_rail_n", setup.model.weightPerRail()},
                {"wheels", passageWheels(setup, run, forces)},
                {"max_newton_iterations", run.maxNewtonIterations()},
                {"setup_time_s", t_setup},
                {"wall_time_s", wall},
                {"out", dir}});
  if (setup.model.fullWidth()) summary["width"] = "full";  // the half width's JSON is unchanged
  addResilientWheels(setup.model.params(), summary);
  printJson(summary);
  return 0;
}

const Registrar reg_modes("vehicle-modes", "vehicle modes (rigid | flexible track), named, f0 and damping",
                          vehicleModes);
const Registrar reg_imp("wheel-impedance", "wheel impedance F/v (rigid | flexible track) to CSV", wheelImpedance);
const Registrar reg_pass("passage", "coupled vehicle/track passage: contact forces, soil loads, summary", passage);

}  // namespace
}  // namespace railvib::tool
