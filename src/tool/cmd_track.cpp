// railvib_tool track commands: receptance, moving-load, track-bench.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <tuple>

#include "command_registry.hpp"
#include "railvib/coupling/track_on_soil.hpp"
#include "railvib/io/csv.hpp"
#include "railvib/signal/decimator.hpp"
#include "railvib/track/track_analysis.hpp"
#include "railvib/track/track_newmark.hpp"
#include "railvib/track/track_stepper.hpp"
#include "railvib/vehicle/vehicle_model.hpp"
#include "railvib/vehicle/vehicle_params.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using nlohmann::json;
using track::FoundationModel;
using track::Rail;
using track::RailLoading;
using track::TrackModel;
using track::TrackParams;

std::string fmt(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

/// The --foundation option as a config override (none when not given).
std::vector<std::string> foundationOverride(const ArgParser& args) {
  if (!args.has("foundation")) return {};
  return {"track.foundation.model=" + args.get("foundation")};
}

/// Config with --set, then --foundation, applied.
Config loadWithFoundation(const ArgParser& args) { return loadConfig(args, foundationOverride(args)); }

// A positive option within [lo, hi].
double positiveOption(const ArgParser& args, const std::string& name, double lo, double hi) {
  return args.getDouble(name, lo, hi);
}

// ------------------------------------------------------------------ receptance
/// A resilient layer as configured and as modelled (spring and damper per rail seat).
json layerJson(const track::ResilientLayer& l) {
  return {{"bedding_modulus_n_mm3", l.bedding_modulus_n_mm3},
          {"bearing_area_per_rail_seat_m2", l.bearing_area_m2},
          {"loss_factor", l.loss_factor},
          {"reference_frequency_hz", l.reference_frequency_hz},
          {"stiffness_n_m", l.stiffnessNPerM()},
          {"damping_n_s_m", l.dampingNsPerM()}};
}

int runReceptance(const std::vector<std::string>& argv) {
  ArgParser args("receptance",
                 "direct point receptance of the rail (m/N) from the track model's M, C, K; CSV f_hz,re,im,abs");
  addConfigOptions(args);
  args.option(
          "foundation",
          "clm | winkler | rigid (default: track.foundation.model) | fe_soil: the ballast on the scenario's FE soil "
          "(paper Fig. 4's rigorous model; one soil impulse run, about a minute on the Haren mesh)")
      .option("soil-duration", "fe_soil: simulated time of the soil's impulse run (s; default 1.5)")
      .option("soil-pulse", "fe_soil: duration of its Hann force pulse (s; default 0.02)")
      .option("reach", "fe_soil: the soil couples sleepers up to this many apart (default: as far as the box reads)")
      .option("at", "midspan | sleeper (the sleeper nearest x = 0, or the midspan after it)", "sleeper")
      .option("fmin", "lowest frequency (Hz)", "1")
      .option("fmax", "highest frequency (Hz)", "500")
      .option("df", "frequency step (Hz)", "0.5")
      .option("csv", "output CSV file")
      .option("vary", "kb | kf: sweep the ballast or foundation stiffness by --factors (others fixed)")
      .option("factors", "comma-separated stiffness factors of --vary", "0.5,0.75,1,1.5,2")
      .option("load",
              "left | right | both | anti: the rails loaded, 1 N each (both: in phase, anti: left down, right up); "
              "the receptance is the left rail's (the right's for right). right and anti need track.width: full",
              "left");
  if (!args.parse(argv)) return 0;
  if (!args.has("csv")) throw ArgError("receptance: --csv OUT is required");
  const std::string load_name = args.get("load");
  const std::map<std::string, RailLoading> loadings{{"left", RailLoading::Left},
                                                    {"right", RailLoading::Right},
                                                    {"both", RailLoading::Both},
                                                    {"anti", RailLoading::AntiPhase}};
  if (!loadings.count(load_name)) throw ArgError("--load must be left, right, both or anti");
  const RailLoading loading = loadings.at(load_name);
  const std::string at = args.get("at");
  if (at != "midspan" && at != "sleeper") throw ArgError("--at must be midspan or sleeper");
  const double fmin = positiveOption(args, "fmin", 1e-3, 1e5), fmax = positiveOption(args, "fmax", 1e-3, 1e5),
               df = positiveOption(args, "df", 1e-3, 1e3);
  if (fmax <= fmin) throw ArgError("--fmax must be greater than --fmin");
  if ((fmax - fmin) / df > 200000) throw ArgError("--df too small: more than 200000 frequencies");
  std::string vary = args.has("vary") ? args.get("vary") : "";
  if (!vary.empty() && vary != "kb" && vary != "kf") throw ArgError("--vary must be kb or kf");
  const std::vector<double> factors = vary.empty() ? std::vector<double>{1.0} : args.getDoubles("factors", 1e-6, 1e6);
  const bool fe_soil = args.has("foundation") && args.get("foundation") == "fe_soil";
  if (fe_soil && vary == "kf") throw ArgError("--vary kf: the FE soil has no foundation stiffness (vary its layers)");
  for (const char* option : {"soil-duration", "soil-pulse", "reach"}) {
    if (!fe_soil && args.has(option)) {
      throw ArgError(std::string("--") + option + " applies to --foundation fe_soil only");
    }
  }

  // fe_soil: the track's own foundation is set aside (track::receptanceOnGround), the soil comes from `soil`.
  const Config cfg = fe_soil ? loadConfig(args) : loadWithFoundation(args);
  const TrackParams base = track::loadTrackParams(cfg.root());
  std::unique_ptr<soil::FootprintCompliance> soil;
  size_t reach = std::numeric_limits<size_t>::max();
  if (fe_soil) {
    if (base.width != track::TrackWidth::Half)
      throw ArgError("--foundation fe_soil takes the half track (track.width: half)");
    soil::FootprintComplianceSpec spec;
    if (args.has("soil-duration")) spec.duration_s = positiveOption(args, "soil-duration", 1e-4, 60.0);
    if (args.has("soil-pulse")) spec.pulse_s = positiveOption(args, "soil-pulse", 1e-5, 10.0);
    if (args.has("reach")) {
      const double r = positiveOption(args, "reach", 1e-3, 1e4);
      if (r != std::floor(r) || r > 1e6) throw ArgError("--reach must be a whole number of sleepers");
      reach = static_cast<size_t>(r);
    }
    const soil::SoilParams soil_params = soil::loadSoilParams(cfg.root());
    const double f_max = soil_params.mesh.f_max_hz;
    if (fmax > f_max * (1.0 + 1e-9)) {
      throw ArgError("--fmax " + fmt(fmax) + " Hz is above the soil mesh's f_max " + fmt(f_max) +
                     " Hz (soil.mesh.f_max_hz): the FE soil does not resolve it");
    }
    soil = std::make_unique<soil::FootprintCompliance>(soil_params, spec);
  }
  if (base.width == track::TrackWidth::Half && (loading == RailLoading::Right || loading == RailLoading::AntiPhase)) {
    throw ArgError("--load " + load_name + " needs both rails: --set track.width=full (the half track has one rail)");
  }
  std::vector<double> f;
  for (long i = 0;; ++i) {
    const double v = fmin + static_cast<double>(i) * df;
    if (v > fmax + 1e-9 * df) break;
    f.push_back(v);
  }
  // Position: the sleeper nearest x = 0 (inside the rail), or the midspan after it.
  const TrackModel probe(base);
  const auto& xs = probe.sleeperPositions();
  const size_t i0 = std::min(static_cast<size_t>(probe.nearestSleeper(0.0)), xs.size() - 2);
  const double x = at == "sleeper" ? xs[i0] : xs[i0] + 0.5 * base.layout.spacing_m;
  const double fpp = track::pinnedPinnedFrequency(base);

  std::vector<std::string> columns{"f_hz"};
  auto suffix = [&](double factor) { return vary.empty() ? std::string() : "_" + vary + "_x" + fmt(factor); };
  for (double factor : factors) {
    for (const char* c : {"re", "im", "abs"}) columns.push_back(c + suffix(factor));
  }
  std::vector<std::vector<std::complex<double>>> curves;
  json runs = json::array();
  for (double factor : factors) {
    TrackParams p = base;
    if (vary == "kb") p.ballast_stiffness_n_m *= factor;  // Winkler k_f stays at its nominal value
    if (vary == "kf") {
      p.clm.stiffness_n_m *= factor;
      p.winkler.stiffness_n_m *= factor;
    }
    const TrackModel model(p);
    curves.push_back(fe_soil ? coupling::feSoilReceptance(p, *soil, x, f, reach) : model.receptance(x, f, loading));
    std::vector<track::PointLoad> unit;
    const bool full = model.railCount() == 2;
    if (loading != RailLoading::Right) unit.push_back({x, 1.0, Rail::Left});
    if (full && loading != RailLoading::Left)
      unit.push_back({x, loading == RailLoading::AntiPhase ? -1.0 : 1.0, Rail::Right});
    const Rail observed = loading == RailLoading::Right ? Rail::Right : Rail::Left;
    const Eigen::VectorXd u = model.staticDeflection(unit);
    json peaks = json::array();
    int resonance = 0;
    for (const auto& pk : track::findPeaks(f, curves.back())) {
      std::string kind;
      if (pk.frequency_hz > 0.8 * fpp && pk.frequency_hz < 1.2 * fpp) {
        kind = "pinned_pinned";
      } else if (fe_soil) {
        kind = "resonance";
      } else if (pk.frequency_hz < 0.8 * fpp) {
        kind = resonance == 0   ? (p.foundation == FoundationModel::Clm ? "in_phase_rail_ballast_foundation"
                                                                        : "in_phase_rail_sleeper")
               : resonance == 1 ? "out_of_phase_rail_ballast"
                                : "other";
        ++resonance;
      } else {
        kind = "other";
      }
      peaks.push_back({{"frequency_hz", pk.frequency_hz}, {"magnitude_m_n", pk.magnitude_m_n}, {"mode", kind}});
    }
    json run = {{"peaks", peaks}};
    // The FE soil has no static solve here (its lowest frequency stands for it).
    if (!fe_soil) run["static_receptance_m_n"] = model.railPoint(x, observed).displacement(u);
    if (!vary.empty()) {
      run["factor"] = factor;
      run[vary == "kb" ? "ballast_stiffness_n_m" : "foundation_stiffness_n_m"] =
          vary == "kb" ? p.ballast_stiffness_n_m
                       : (p.foundation == FoundationModel::Clm ? p.clm.stiffness_n_m : p.winkler.stiffness_n_m);
    }
    runs.push_back(run);
  }
  io::CsvWriter csv(args.get("csv"), columns);
  std::vector<double> row(columns.size());
  for (size_t i = 0; i < f.size(); ++i) {
    row[0] = f[i];
    for (size_t k = 0; k < curves.size(); ++k) {
      row[1 + 3 * k] = curves[k][i].real();
      row[2 + 3 * k] = curves[k][i].imag();
      row[3 + 3 * k] = std::abs(curves[k][i]);
    }
    csv.row(row);
  }
  csv.commit();
  json summary = {{"command", "receptance"},
                  {"foundation", fe_soil ? std::string("fe_soil") : track::foundationName(base.foundation)},
                  {"width", base.width == track::TrackWidth::Full ? "full" : "half"},
                  {"load", load_name},
                  {"at", at},
                  {"x_m", x},
                  {"f_pinned_pinned_hz", fpp},
                  {"frequencies", f.size()},
                  {"csv", args.get("csv")}};
  if (soil) summary["soil_run"] = soil->summary();
  // the resilient layers, when configured (absent: the summary as before)
  if (base.under_sleeper_pad) summary["under_sleeper_pad"] = layerJson(*base.under_sleeper_pad);
  if (base.under_ballast_mat) summary["under_ballast_mat"] = layerJson(*base.under_ballast_mat);
  if (vary.empty()) {
    if (!fe_soil) summary["static_receptance_m_n"] = runs[0]["static_receptance_m_n"];
    summary["peaks"] = runs[0]["peaks"];
  } else {
    summary["vary"] = vary;
    summary["runs"] = runs;
  }
  printJson(summary);
  return 0;
}

// ------------------------------------------------------------------ moving-load
int runMovingLoad(const std::vector<std::string>& argv) {
  ArgParser args("moving-load",
                 "constant moving loads on the track; ballast-to-soil loads per sleeper (both rails) to CSV");
  addConfigOptions(args);
  args.option("foundation", "clm | winkler | rigid (default: track.foundation.model)")
      .option("load", "force per wheel and rail (N) at every axle (default: T2000 static wheel loads)")
      .flag("single", "one load only (at the front axle position) instead of the T2000 axles")
      .option("speed", "speed (m/s) (default: simulation.speed_m_s)")
      .option("duration", "simulated time (s) (default: simulation.duration_s)")
      .option("start", "front axle position at t = 0 (m) (default: simulation.front_axle_start_m)")
      .option("dt", "time step (s) (default: simulation.time_step_s)")
      .option("rate", "output sample rate (Hz), anti-alias decimated (default: track.output.load_sample_rate_hz)")
      .option("csv", "output CSV: t_s, then one column per sleeper (x_<position>), N downward, both rails");
  if (!args.parse(argv)) return 0;
  if (!args.has("csv")) throw ArgError("moving-load: --csv OUT is required");
  const Config cfg = loadWithFoundation(args);
  const ConfigNode root = cfg.root();
  const TrackParams params = track::loadTrackParams(cfg.root());
  const vehicle::PassageParams sim = vehicle::loadPassageParams(root);
  const double speed = args.has("speed") ? args.getDouble("speed", 0.0, 150.0) : sim.speed_m_s;
  const double duration = args.has("duration") ? positiveOption(args, "duration", 1e-4, 3600.0) : sim.duration_s;
  const double start = args.has("start") ? args.getDouble("start", -1e5, 1e5) : sim.front_axle_start_m;
  const double dt = args.has("dt") ? positiveOption(args, "dt", 1e-8, 1.0) : sim.time_step_s;
  const double rate = args.has("rate") ? positiveOption(args, "rate", 1.0, 1e7) : params.load_sample_rate_hz;
  if (!std::isfinite(speed) || speed < 0.0) throw ArgError("--speed must be >= 0");
  if (rate > 1.0 / dt * (1.0 + 1e-9)) throw ArgError("--rate must not exceed the step rate 1/dt");
  const bool single = args.isSet("single");

  track::MovingLoadRun run;
  run.dt_s = dt;
  run.duration_s = duration;
  run.front_start_m = start;
  run.speed_m_s = speed;
  std::string load_source;
  if (single) {
    run.offsets_behind_m = {0.0};
  } else {
    run.offsets_behind_m = vehicle::loadVehicleParams(root).axleOffsets();
  }
  if (args.has("load")) {
    const double load = args.getDouble("load", -1e7, 1e7);
    if (!std::isfinite(load)) throw ArgError("--load must be finite");
    run.forces_n.assign(run.offsets_behind_m.size(), load);
    load_source = "--load";
  } else {
    const vehicle::VehicleModel vehicle_model(vehicle::loadVehicleParams(root));
    const std::vector<double> wheel = vehicle::uniformStaticWheelLoadsPerRail(vehicle_model);
    run.forces_n.assign(run.offsets_behind_m.size(), wheel.front());
    load_source = vehicle_model.params().name + " static: weight per rail / axles, per wheel and rail";
  }
  const TrackModel model(params);
  const size_t ns = static_cast<size_t>(model.sleeperCount());
  std::vector<std::string> columns{"t_s"};
  for (double x : model.sleeperPositions()) columns.push_back("x_" + fmt(x));

  const double step_rate = 1.0 / dt;
  const bool decimate = rate < step_rate * (1.0 - 1e-9);
  std::unique_ptr<signal::Decimator> dec;
  if (decimate) dec = std::make_unique<signal::Decimator>(signal::DecimatorSpec{step_rate, rate}, ns, 0.0);

  io::CsvWriter csv(args.get("csv"), columns);
  std::vector<double> frame(ns), out, row(ns + 1);
  size_t rows = 0;
  double peak = 0.0, worst_sum = 0.0;
  const double applied = 2.0 * std::accumulate(run.forces_n.begin(), run.forces_n.end(), 0.0);
  auto emit = [&](const std::vector<double>& data) {
    for (size_t k = 0; k + ns <= data.size(); k += ns) {
      row[0] = decimate ? dec->outputTime(rows) : static_cast<double>(rows) * dt;
      std::copy(data.begin() + static_cast<long>(k), data.begin() + static_cast<long>(k + ns), row.begin() + 1);
      csv.row(row);
      ++rows;
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  track::simulateMovingLoads(model, run, [&](double t, const std::vector<double>& b) {
    double sum = 0.0;
    for (size_t i = 0; i < ns; ++i) {
      frame[i] = track::kHalfTrackRailsOnSoil * b[i];
      sum += frame[i];
      peak = std::max(peak, std::abs(frame[i]));
    }
    if (t > 0.5 && applied != 0.0) worst_sum = std::max(worst_sum, std::abs(sum / applied - 1.0));
    if (decimate) {
      out.clear();
      dec->push(frame.data(), 1, out);
      emit(out);
    } else {
      emit(frame);
    }
  });
  if (decimate) {
    out.clear();
    dec->flush(out);
    emit(out);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  csv.commit();
  const long steps = static_cast<long>(std::llround(duration / dt));
  printJson({{"command", "moving-load"},
             {"foundation", track::foundationName(params.foundation)},
             {"sleepers", ns},
             {"sleeper_x_range_m", {model.sleeperPositions().front(), model.sleeperPositions().back()}},
             {"loads_per_rail_n", run.forces_n},
             {"load_source", load_source},
             {"axle_offsets_m", run.offsets_behind_m},
             {"speed_m_s", speed},
             {"duration_s", duration},
             {"time_step_s", dt},
             {"steps", steps},
             {"output_rate_hz", decimate ? rate : step_rate},
             {"rows", rows},
             {"csv", args.get("csv")},
             {"peak_soil_load_n", peak},
             {"max_rel_error_sum_soil_loads_vs_applied_after_0_5_s", worst_sum},
             {"wall_time_s", wall},
             {"us_per_step", 1e6 * wall / static_cast<double>(std::max(1L, steps))}});
  return 0;
}

// ------------------------------------------------------------------ track-bench
/// CPU time of this thread (s): robust against other processes sharing the cores.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double medianOf(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int runTrackBench(const std::vector<std::string>& argv) {
  ArgParser args("track-bench", "time per Newmark step of the track alone (100 m track), microseconds");
  addConfigOptions(args);
  args.option("foundation", "clm | winkler | rigid (default: track.foundation.model)")
      .option("length", "track length (m), centred on x = 0", "100")
      .option("dt", "time step (s)", "1e-5")
      .option("steps", "steps per repeat", "20000")
      .option("repeats", "repeats (the median is reported)", "5");
  if (!args.parse(argv)) return 0;
  const double length = positiveOption(args, "length", 1e-2, 1e4);
  std::vector<std::string> overrides = foundationOverride(args);
  overrides.push_back("track.extent.mode=fixed");
  overrides.push_back("track.extent.x_min_m=" + fmt(-0.5 * length));
  overrides.push_back("track.extent.x_max_m=" + fmt(0.5 * length));
  const Config cfg = loadConfig(args, overrides);
  const TrackParams params = track::loadTrackParams(cfg.root());
  const double dt = positiveOption(args, "dt", 1e-8, 1.0);
  const long steps = args.getInt("steps", 1, 100000000), repeats = args.getInt("repeats", 1, 1000);
  if (steps < 1 || repeats < 1) throw ArgError("--steps and --repeats must be >= 1");
  const TrackModel model(params);
  const std::vector<double> offsets{0.0, 1.6667, 7.5, 9.1667, 15.0, 16.6667};
  json solvers = json::array();
  for (auto kind : {track::TrackSolverKind::EigenSimplicialLLT, track::TrackSolverKind::CholmodSupernodalLLT}) {
    track::TrackNewmark nm(model, dt, kind);
    std::vector<double> plain, coupled, plain_cpu, coupled_cpu;
    std::vector<track::PointLoad> loads(offsets.size());
    std::vector<track::RailPoint> pts(offsets.size());
    std::vector<double> forces(offsets.size(), 26e3);
    for (long r = 0; r < repeats; ++r) {
      nm.setStaticEquilibrium({});
      double c0 = threadCpuSeconds();
      auto t0 = std::chrono::steady_clock::now();
      for (long n = 0; n < steps; ++n) {
        const double front = 5.0 + 8.33 * dt * static_cast<double>(n);
        for (size_t k = 0; k < offsets.size(); ++k) loads[k] = {front - offsets[k], 26e3};
        nm.step(loads);
      }
      auto t1 = std::chrono::steady_clock::now();
      plain_cpu.push_back(1e6 * (threadCpuSeconds() - c0) / static_cast<double>(steps));
      plain.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / static_cast<double>(steps));
      c0 = threadCpuSeconds();
      t0 = std::chrono::steady_clock::now();
      for (long n = 0; n < steps; ++n) {
        const double front = 5.0 + 8.33 * dt * static_cast<double>(n);
        for (size_t k = 0; k < offsets.size(); ++k) pts[k] = model.railPoint(front - offsets[k]);
        nm.predict();
        nm.setContactPoints(pts);
        nm.commitContact(forces);
      }
      t1 = std::chrono::steady_clock::now();
      coupled_cpu.push_back(1e6 * (threadCpuSeconds() - c0) / static_cast<double>(steps));
      coupled.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / static_cast<double>(steps));
    }
    solvers.push_back({{"solver", kind == track::TrackSolverKind::EigenSimplicialLLT ? "eigen_simplicial_llt"
                                                                                     : "cholmod_supernodal_llt"},
                       {"us_per_step_moving_loads_median", medianOf(plain)},
                       {"us_per_coupled_step_6_contacts_median", medianOf(coupled)},
                       {"cpu_us_per_step_moving_loads_median", medianOf(plain_cpu)},
                       {"cpu_us_per_coupled_step_6_contacts_median", medianOf(coupled_cpu)},
                       {"us_per_step_all", plain},
                       {"us_per_coupled_step_all", coupled}});
  }
  printJson({{"command", "track-bench"},
             {"foundation", track::foundationName(params.foundation)},
             {"length_m", model.railEnd() - model.railStart()},
             {"dofs", model.dofCount()},
             {"sleepers", model.sleeperCount()},
             {"time_step_s", dt},
             {"steps", steps},
             {"repeats", repeats},
             {"solvers", solvers}});
  return 0;
}

// ------------------------------------------------------------------ insertion-loss
/// Largest |a/b - 1| of two curves over the frequencies up to f_max (Hz), and where it is.
std::pair<double, double> worstRelativeError(const std::vector<double>& f, const std::vector<std::complex<double>>& a,
                                             const std::vector<std::complex<double>>& b, double f_max) {
  double worst = 0.0, at = 0.0;
  for (size_t i = 0; i < f.size(); ++i) {
    if (f[i] > f_max) break;
    const double e = std::abs(std::abs(a[i]) / std::abs(b[i]) - 1.0);
    if (e > worst) {
      worst = e;
      at = f[i];
    }
  }
  return {worst, at};
}

int runInsertionLoss(const std::vector<std::string>& argv) {
  ArgParser args("insertion-loss",
                 "a resilient layer (under-sleeper pad | under-ballast mat, from its config section) against the "
                 "track without it: rail receptance and force transmissibility to the foundation, both against the "
                 "continuous beam's closed form (rigid and Winkler bases), and the insertion loss of the force");
  addConfigOptions(args);
  args.option("measure", "usp (track.under_sleeper_pad) | ubm (track.under_ballast_mat) | both", "usp")
      .option("foundation", "clm | winkler | rigid (default: track.foundation.model)")
      .option("at", "midspan | sleeper (the load at the sleeper nearest x = 0, or the midspan after it)", "sleeper")
      .option("fmin", "lowest frequency (Hz)", "1")
      .option("fmax", "highest frequency (Hz)", "400")
      .option("df", "frequency step (Hz)", "0.5")
      .option("band",
              "the closed-form comparison's upper frequency (Hz; also reported up to f_pp / 2, where the discrete "
              "supports depart by a few %)",
              "150")
      .option("csv",
              "output CSV: f_hz, receptance and transmissibility without / with (discrete and closed form), "
              "insertion loss (dB)");
  if (!args.parse(argv)) return 0;
  const std::string measure = args.get("measure"), at = args.get("at");
  if (measure != "usp" && measure != "ubm" && measure != "both") throw ArgError("--measure must be usp, ubm or both");
  if (at != "midspan" && at != "sleeper") throw ArgError("--at must be midspan or sleeper");
  const double fmin = positiveOption(args, "fmin", 1e-3, 1e5), fmax = positiveOption(args, "fmax", 1e-3, 1e5),
               df = positiveOption(args, "df", 1e-3, 1e3);
  if (fmax <= fmin) throw ArgError("--fmax must be greater than --fmin");
  if ((fmax - fmin) / df > 200000) throw ArgError("--df too small: more than 200000 frequencies");
  const double band = positiveOption(args, "band", 1e-3, 1e4);
  // the measure's section switched on (its values as configured), the other layer taken out
  std::vector<std::string> on = foundationOverride(args);
  if (measure != "ubm") on.push_back("track.under_sleeper_pad.enabled=true");
  if (measure != "usp") on.push_back("track.under_ballast_mat.enabled=true");
  const Config cfg = loadConfig(args, on);
  TrackParams with = track::loadTrackParams(cfg.root());
  if (measure == "usp") with.under_ballast_mat.reset();
  if (measure == "ubm") with.under_sleeper_pad.reset();
  TrackParams without = with;
  without.under_sleeper_pad.reset();
  without.under_ballast_mat.reset();

  std::vector<double> f;
  for (long i = 0;; ++i) {
    const double v = fmin + static_cast<double>(i) * df;
    if (v > fmax + 1e-9 * df) break;
    f.push_back(v);
  }
  const TrackModel model_without(without), model_with(with);
  const auto& xs = model_with.sleeperPositions();
  const size_t i0 = std::min(static_cast<size_t>(model_with.nearestSleeper(0.0)), xs.size() - 2);
  const double x = at == "sleeper" ? xs[i0] : xs[i0] + 0.5 * with.layout.spacing_m;
  const RailLoading loading = model_with.railCount() == 2 ? RailLoading::Both : RailLoading::Left;
  const auto r0 = model_without.receptance(x, f, loading), r1 = model_with.receptance(x, f, loading);
  const auto t0 = track::foundationForceTransmissibility(model_without, x, f, loading);
  const auto t1 = track::foundationForceTransmissibility(model_with, x, f, loading);
  std::vector<double> il(f.size());
  for (size_t i = 0; i < f.size(); ++i) il[i] = track::insertionLossDb(t0[i], t1[i]);
  const double fpp = track::pinnedPinnedFrequency(with);

  // the closed form of the same layered support (continuous beam; not for the CLM)
  const bool closed = with.foundation != FoundationModel::Clm;
  std::vector<std::complex<double>> cr0, cr1, ct0, ct1;
  std::vector<double> cil;
  if (closed) {
    for (double fi : f) {
      cr0.push_back(track::continuousBeamReceptance(without, fi));
      cr1.push_back(track::continuousBeamReceptance(with, fi));
      ct0.push_back(track::continuousBeamForceTransmissibility(without, fi));
      ct1.push_back(track::continuousBeamForceTransmissibility(with, fi));
      cil.push_back(track::insertionLossDb(ct0.back(), ct1.back()));
    }
  }
  if (args.has("csv")) {
    std::vector<std::string> columns{
        "f_hz",       "abs_receptance_without_m_n", "abs_receptance_with_m_n", "abs_t_without",
        "abs_t_with", "insertion_loss_db"};
    if (closed) {
      for (const char* c : {"closed_abs_receptance_without_m_n", "closed_abs_receptance_with_m_n",
                            "closed_abs_t_without", "closed_abs_t_with", "closed_insertion_loss_db"})
        columns.push_back(c);
    }
    io::CsvWriter csv(args.get("csv"), columns);
    std::vector<double> row;
    for (size_t i = 0; i < f.size(); ++i) {
      row = {f[i], std::abs(r0[i]), std::abs(r1[i]), std::abs(t0[i]), std::abs(t1[i]), il[i]};
      if (closed) {
        for (double v : {std::abs(cr0[i]), std::abs(cr1[i]), std::abs(ct0[i]), std::abs(ct1[i]), cil[i]})
          row.push_back(v);
      }
      csv.row(row);
    }
    csv.commit();
  }
  const auto lowest = std::min_element(il.begin(), il.end());
  json summary = {{"command", "insertion-loss"},
                  {"measure", measure},
                  {"foundation", track::foundationName(with.foundation)},
                  {"width", with.width == track::TrackWidth::Full ? "full" : "half"},
                  {"at", at},
                  {"x_m", x},
                  {"f_pinned_pinned_hz", fpp},
                  {"frequencies", f.size()},
                  {"insertion_loss_crossings_hz", track::zeroCrossings(f, il)},
                  {"min_insertion_loss_db", *lowest},
                  {"f_at_min_insertion_loss_hz", f[static_cast<size_t>(lowest - il.begin())]},
                  {"insertion_loss_at_fmax_db", il.back()},
                  {"csv", args.has("csv") ? args.get("csv") : ""}};
  if (with.under_sleeper_pad) summary["under_sleeper_pad"] = layerJson(*with.under_sleeper_pad);
  if (with.under_ballast_mat) summary["under_ballast_mat"] = layerJson(*with.under_ballast_mat);
  json peaks = json::array();
  for (const auto& pk : track::findPeaks(f, t1))
    peaks.push_back({{"frequency_hz", pk.frequency_hz}, {"abs_t", pk.magnitude_m_n}});
  summary["transmissibility_peaks_with"] = peaks;
  if (closed) {
    // the discrete supports follow the continuous beam below the pinned-pinned frequency: compared up to --band
    // and up to f_pp / 2
    const std::vector<
        std::tuple<std::string, const std::vector<std::complex<double>>*, const std::vector<std::complex<double>>*>>
        pairs{{"receptance_without", &r0, &cr0},
              {"receptance_with", &r1, &cr1},
              {"transmissibility_without", &t0, &ct0},
              {"transmissibility_with", &t1, &ct1}};
    for (const auto& [key, limit] : {std::pair{"closed_form_errors_up_to_band", band},
                                     std::pair{"closed_form_errors_up_to_half_f_pp", 0.5 * fpp}}) {
      json errors = {{"up_to_hz", std::min(limit, f.back())}};
      for (const auto& [name, a, b] : pairs) {
        const auto [worst, where] = worstRelativeError(f, *a, *b, limit);
        errors[name] = {{"max_relative_error", worst}, {"at_hz", where}};
      }
      summary[key] = errors;
    }
    summary["closed_form_insertion_loss_crossings_hz"] = track::zeroCrossings(f, cil);
    summary["closed_form_min_insertion_loss_db"] = *std::min_element(cil.begin(), cil.end());
  } else {
    summary["closed_form"] = "none for the CLM foundation (masses coupled along the track): --foundation rigid|winkler";
  }
  printJson(summary);
  return 0;
}

const Registrar kReceptance("receptance", "rail point receptance of the track model (CSV + peaks)", runReceptance);
const Registrar kMovingLoad("moving-load", "constant moving loads: ballast-to-soil loads per sleeper (CSV)",
                            runMovingLoad);
const Registrar kInsertionLoss("insertion-loss",
                               "a resilient layer (USP / UBM): receptance, force transmissibility, insertion loss",
                               runInsertionLoss);
const Registrar kTrackBench("track-bench", "microseconds per Newmark step of the track (100 m)", runTrackBench);

}  // namespace
}  // namespace railvib::tool
