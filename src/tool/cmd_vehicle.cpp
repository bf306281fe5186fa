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
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using nlohmann::json;
using namespace railvib::vehicle;

std::string trackChoice(const ArgParser& p) {
  const std::string t = p.get("track");
  if (t != "rigid" && t != "flexible") throw ArgError("--track must be rigid or flexible, got '" + t + "'");
  return t;
}

json modesJson(const std::vector<Mode>& modes, bool flexible) {
  json arr = json::array();
  for (const auto& m : modes) {
    json j = {{"name", m.name},
              {"body", m.body},
              {"f0_hz", m.frequency_hz},
              {"damping_ratio", m.damping_ratio},
              {"name_energy_share", m.name_share}};
    if (flexible) j["vehicle_energy_share"] = m.vehicle_energy_share;
    if (std::isfinite(m.pivot_offset_m)) j["pivot_behind_bogie_centre_m"] = m.pivot_offset_m;
    arr.push_back(j);
  }
  return arr;
}

int vehicleModes(const std::vector<std::string>& args) {
  ArgParser p("vehicle-modes", "eigenanalysis of the T2000 linearised about static equilibrium");
  addConfigOptions(p);
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
  const Config cfg = loadConfig(p, extra);
  const auto t0 = std::chrono::steady_clock::now();
  const VehicleModel model(loadVehicleParams(cfg.root()));
  std::vector<Mode> modes;
  if (track == "rigid") {
    modes = vehicleModesRigid(model);
  } else {
    const auto tp = track::loadTrackParams(cfg.section("track"));
    ModalOptions mo;
    mo.min_vehicle_energy_share = p.getDouble("min-vehicle-share");
    mo.margin_m = p.getDouble("margin");
    modes = vehicleModesFlexible(model, tp, mo);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  json out = {{"track", track},
              {"dof", model.dofCount()},
              {"wall_time_s", wall},
              {"modes", modesJson(modes, track == "flexible")}};
  if (track == "rigid") {
    out["linearised_hertz_stiffness_n_m"] = linearisedHertzStiffness(model);
  }
  printJson(out);
  return 0;
}

int wheelImpedance(const std::vector<std::string>& args) {
  ArgParser p("wheel-impedance", "direct impedance F/v of a wheel (tread) of the T2000, frequency domain");
  addConfigOptions(p);
  p.option("wheel", "axle index 0..5 (0: leading bogie motor wheel, 2: middle bogie motor wheel)", "0");
  p.option("track", "rigid | flexible", "rigid");
  p.option("csv", "output CSV (f_hz, |Z| N s/m, phase deg, Re, Im)");
  p.option("f-min", "lowest frequency (Hz)", "1");
  p.option("f-max", "highest frequency (Hz)", "200");
  p.option("points", "log-spaced frequencies", "300");
  if (!p.parse(args)) return 0;
  const std::string track = trackChoice(p);
  const Config cfg = loadConfig(p);
  const VehicleModel model(loadVehicleParams(cfg.root()));
  const int wheel = static_cast<int>(p.getInt("wheel"));
  if (wheel < 0 || wheel >= model.wheelCount())
    throw ArgError("--wheel must be in 0.." + std::to_string(model.wheelCount() - 1));
  const double f0 = p.getDouble("f-min"), f1 = p.getDouble("f-max");
  const long n = p.getInt("points");
  if (!(f0 > 0.0 && f1 > f0 && n >= 2)) throw ArgError("need 0 < --f-min < --f-max and --points >= 2");
  std::vector<double> f(static_cast<size_t>(n));
  for (long k = 0; k < n; ++k) f[static_cast<size_t>(k)] = f0 * std::pow(f1 / f0, static_cast<double>(k) / (n - 1));
  const auto t0 = std::chrono::steady_clock::now();
  const auto Z = track == "rigid"
                     ? wheelImpedanceRigid(model, wheel, f)
                     : wheelImpedanceFlexible(model, track::loadTrackParams(cfg.section("track")), wheel, f);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  size_t imin = 0;
  for (size_t k = 0; k < Z.size(); ++k) {
    if (std::abs(Z[k]) < std::abs(Z[imin])) imin = k;
  }
  if (p.has("csv") && !p.get("csv").empty()) {
    io::CsvWriter csv(p.get("csv"), {"f_hz", "abs_z_n_s_m", "phase_deg", "re_z_n_s_m", "im_z_n_s_m"});
    for (size_t k = 0; k < Z.size(); ++k) {
      csv.row({f[k], std::abs(Z[k]), std::arg(Z[k]) * 180.0 / M_PI, Z[k].real(), Z[k].imag()});
    }
    csv.commit();
  }
  printJson({{"wheel", wheel},
             {"axle_type", model.wheels()[wheel].type == AxleType::Motor ? "motor" : "trailer"},
             {"track", track},
             {"points", n},
             {"min_abs_z_n_s_m", std::abs(Z[imin])},
             {"f_at_min_abs_z_hz", f[imin]},
             {"csv", p.has("csv") ? p.get("csv") : ""},
             {"wall_time_s", wall}});
  return 0;
}

int passage(const std::vector<std::string>& args) {
  ArgParser p("passage", "coupled T2000 / track passage over the defect (contact forces, soil loads, summary)");
  addConfigOptions(p);
  p.option("out", "output directory");
  p.option("speed", "speed (m/s; default simulation.speed_m_s)", "");
  p.option("duration", "simulated time (s; default simulation.duration_s)", "");
  p.option("dt", "time step (s; default simulation.time_step_s)", "");
  p.option("foundation", "clm | winkler (default: config)", "");
  p.option("track", "rigid | flexible", "flexible");
  p.option("csv-every", "write every N-th step to contact_forces.csv / unevenness.csv", "10");
  if (!p.parse(args)) return 0;
  const std::string track = trackChoice(p);
  if (!p.has("out") || p.get("out").empty()) throw ArgError("passage: --out DIR is required");
  std::vector<std::string> extra;
  if (p.has("speed")) extra.push_back("simulation.speed_m_s=" + p.get("speed"));
  if (p.has("duration")) extra.push_back("simulation.duration_s=" + p.get("duration"));
  if (p.has("dt")) extra.push_back("simulation.time_step_s=" + p.get("dt"));
  if (p.has("foundation")) extra.push_back("track.foundation.model=" + p.get("foundation"));
  const Config cfg = loadConfig(p, extra);
  const long every = p.getInt("csv-every");
  if (every < 1) throw ArgError("--csv-every must be >= 1");

  const VehicleModel model(loadVehicleParams(cfg.root()));
  const PassageParams pp = loadPassageParams(cfg.root());
  const UnevennessParams up = loadUnevennessParams(cfg.root());
  const auto tp = track::loadTrackParams(cfg.section("track"));
  const Unevenness unevenness(up, tp.x_min_m, tp.x_max_m);
  std::unique_ptr<RailSupport> rail;
  if (track == "rigid") {
    rail = std::make_unique<RigidRail>();
  } else {
    rail = std::make_unique<FlexibleRail>(tp, pp.time_step_s);
  }
  const auto t_start = std::chrono::steady_clock::now();
  PassageOptions opt;
  opt.record_ballast = track == "flexible";
  VehiclePassage run(model, unevenness, pp, std::move(rail), opt);
  const double t_setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  const std::string dir = p.get("out");
  std::filesystem::create_directories(dir);
  const int nw = model.wheelCount();
  std::vector<std::string> fcols{"t_s"}, zcols{"t_s"};
  for (int i = 0; i < nw; ++i) {
    fcols.push_back("axle" + std::to_string(i) + "_force_n");
    zcols.push_back("axle" + std::to_string(i) + "_unevenness_m");
  }
  io::CsvWriter fcsv(dir + "/contact_forces.csv", fcols);
  io::CsvWriter zcsv(dir + "/unevenness.csv", zcols);
  std::unique_ptr<io::CsvWriter> scsv;
  std::unique_ptr<signal::Decimator> decim;
  const std::vector<double> sleepers = run.rail().sleeperPositions();
  const size_t ns = sleepers.size();
  if (track == "flexible") {
    std::vector<std::string> cols{"t_s"};
    // same header as `railvib_tool moving-load`: x_<sleeper position, 6 significant digits>
    for (size_t s = 0; s < ns; ++s) {
      std::ostringstream name;
      name << "x_" << std::setprecision(6) << sleepers[s];
      cols.push_back(name.str());
    }
    scsv = std::make_unique<io::CsvWriter>(dir + "/soil_loads.csv", cols);
    signal::DecimatorSpec spec;
    spec.input_rate_hz = 1.0 / pp.time_step_s;
    const double ratio = std::round(spec.input_rate_hz / tp.load_sample_rate_hz);
    spec.output_rate_hz = spec.input_rate_hz / std::max(1.0, ratio);
    decim = std::make_unique<signal::Decimator>(spec, ns);
    io::CsvWriter sl(dir + "/sleepers.csv", {"sleeper", "x_m"});
    for (size_t s = 0; s < ns; ++s) sl.row({static_cast<double>(s), sleepers[s]});
    sl.commit();
  }
  std::vector<double> peak(static_cast<size_t>(nw), 0.0), tpeak(static_cast<size_t>(nw), 0.0);
  std::vector<double> minf(static_cast<size_t>(nw), 1e300);
  std::vector<double> soil_in, soil_out, row;
  uint64_t soil_rows = 0;
  auto writeSoil = [&](const std::vector<double>& frames) {
    for (size_t k = 0; k + ns <= frames.size(); k += ns) {
      row.assign(1, decim->outputTime(soil_rows++));
      row.insert(row.end(), frames.begin() + static_cast<long>(k), frames.begin() + static_cast<long>(k + ns));
      scsv->row(row);
    }
  };
  PassageBlock block;
  const uint64_t total = run.totalSamples();
  auto last_print = std::chrono::steady_clock::now();
  while (!run.finished()) {
    const size_t n = run.advance(4096, block);
    for (size_t k = 0; k < n; ++k) {
      const uint64_t idx = block.first_index + k;
      for (int i = 0; i < nw; ++i) {
        const double F = block.contact_force_n[k * nw + i];
        if (F > peak[i]) {
          peak[i] = F;
          tpeak[i] = block.time_s[k];
        }
        minf[i] = std::min(minf[i], F);
      }
      if (idx % static_cast<uint64_t>(every) == 0) {
        row.assign(1, block.time_s[k]);
        for (int i = 0; i < nw; ++i) row.push_back(block.contact_force_n[k * nw + i]);
        fcsv.row(row);
        row.assign(1, block.time_s[k]);
        for (int i = 0; i < nw; ++i) row.push_back(block.unevenness_m[k * nw + i]);
        zcsv.row(row);
      }
    }
    if (decim) {
      soil_in.resize(block.ballast_force_n.size());
      for (size_t k = 0; k < soil_in.size(); ++k) soil_in[k] = 2.0 * block.ballast_force_n[k];
      soil_out.clear();
      decim->push(soil_in.data(), n, soil_out);
      writeSoil(soil_out);
    }
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_print).count() > 5.0) {
      last_print = now;
      const double frac = static_cast<double>(run.nextSampleIndex()) / static_cast<double>(total);
      const double el = std::chrono::duration<double>(now - t_start).count();
      std::cerr << "passage: " << static_cast<int>(100 * frac) << " %, t = " << run.time() << " s, ETA "
                << el * (1.0 - frac) / std::max(frac, 1e-9) << " s\n";
    }
  }
  if (decim) {
    soil_out.clear();
    decim->flush(soil_out);
    writeSoil(soil_out);
    scsv->commit();
  }
  fcsv.commit();
  zcsv.commit();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  const auto& s0 = run.initialState();
  json wheels = json::array();
  for (int i = 0; i < nw; ++i) {
    const double x0 = pp.front_axle_start_m - model.wheels()[i].offset_m;
    const double t_defect =
        up.defect.enabled ? (up.defect.position_m + 0.5 * up.defect.length_m - x0) / pp.speed_m_s : -1.0;
    wheels.push_back({{"axle", i},
                      {"type", model.wheels()[i].type == AxleType::Motor ? "motor" : "trailer"},
                      {"static_force_n", s0.contact_force_n[i]},
                      {"peak_force_n", peak[i]},
                      {"peak_dynamic_force_n", peak[i] - s0.contact_force_n[i]},
                      {"min_force_n", minf[i]},
                      {"time_of_peak_s", tpeak[i]},
                      {"time_over_defect_s", t_defect}});
  }
  printJson({{"track", track},
             {"foundation", track == "flexible" ? track::foundationName(tp.foundation) : "none"},
             {"speed_m_s", pp.speed_m_s},
             {"duration_s", pp.duration_s},
             {"time_step_s", pp.time_step_s},
             {"steps", total - 1},
             {"weight_per_rail_n", model.weightPerRail()},
             {"wheels", wheels},
             {"max_newton_iterations", run.maxNewtonIterations()},
             {"setup_time_s", t_setup},
             {"wall_time_s", wall},
             {"out", dir}});
  return 0;
}

const Registrar reg_modes("vehicle-modes", "T2000 modes (rigid | flexible track), named, f0 and damping", vehicleModes);
const Registrar reg_imp("wheel-impedance", "wheel impedance F/v (rigid | flexible track) to CSV", wheelImpedance);
const Registrar reg_pass("passage", "coupled vehicle/track passage: contact forces, soil loads, summary", passage);

}  // namespace
}  // namespace railvib::tool
