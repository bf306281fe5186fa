// railvib_tool soil commands: soil-bench column|damping|throughput|lamb|reflection|reflection-layered|void-peer, soil.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "command_registry.hpp"
#include "railvib/building/model.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/coupling/house_foundation.hpp"
#include "railvib/io/csv.hpp"
#include "railvib/soil/calculix_peer.hpp"
#include "railvib/soil/lamb.hpp"
#include "railvib/soil/screening.hpp"
#include "railvib/soil/snapshot_io.hpp"
#include "railvib/soil/soil_model.hpp"
#include "railvib/soil/verification.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/vehicle_params.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using nlohmann::json;
using namespace railvib::soil;

// ---------------------------------------------------------------- soil-bench cases
// Each case reads its options from the parsed arguments and fills the JSON summary. To add a case:
// write its function, add a row to kBenchCases (name, what it does) and, if it needs options,
// declare them in soilBench.

struct BenchArgs {
  const ArgParser& p;
  std::vector<Precision> precisions;

  /// Comma-separated list option, at least one value, each within the option's physical range.
  std::vector<double> list(const std::string& key) const {
    static const std::map<std::string, std::pair<double, double>> kRanges = {{"layer", {0.0, 1e3}},
                                                                             {"exponent", {0.0, 10.0}},
                                                                             {"alpha", {0.0, 1e4}},
                                                                             {"pml-thickness", {0.0, 1e3}},
                                                                             {"pml-reflection", {1e-12, 1.0}},
                                                                             {"pml-exponent", {0.0, 10.0}},
                                                                             {"pml-kappa", {1.0, 100.0}},
                                                                             {"pml-alpha", {0.0, 1e4}},
                                                                             {"pml-ratio", {0.0, 1.0}},
                                                                             {"box", {0.1, 1e3}}};
    const auto range = kRanges.at(key);
    return p.getDoubles(key, range.first, range.second);
  }
  /// The product of --layer x --exponent x --alpha, with --layer-bottom.
  void addLayerCases(std::vector<ReflectionCase>& cases) const {
    for (double layer : list("layer")) {
      for (double n : list("exponent")) {
        for (double alpha : list("alpha")) {
          cases.push_back(ReflectionCase::gradedLayer(layer, alpha, n, p.getInt("layer-bottom", 0, 1) != 0));
        }
      }
    }
  }
  /// The product of the --pml-* lists (none when --pml-thickness is empty).
  std::vector<ReflectionCase> pmlCases() const {
    std::vector<ReflectionCase> cases;
    if (!p.has("pml-thickness")) return cases;  // has(): given, or a non-empty default (get() would refuse)
    for (double thickness : list("pml-thickness")) {
      for (double r : list("pml-reflection")) {
        for (double n : list("pml-exponent")) {
          for (double kappa : list("pml-kappa")) {
            for (double alpha : list("pml-alpha")) {
              for (double ratio : list("pml-ratio")) {
                PmlSpec s;
                s.thickness_m = thickness;
                s.reflection_coefficient = r;
                s.exponent = n;
                s.max_kappa = kappa;
                s.alpha_1_s = alpha;
                s.perpendicular_ratio = ratio;
                s.bottom = p.getInt("pml-bottom", 0, 1) != 0;
                s.outer_dashpots = p.getInt("pml-outer-dashpots", 0, 1) != 0;
                cases.push_back(ReflectionCase::pml(s));
              }
            }
          }
        }
      }
    }
    return cases;
  }
};

const char* precisionName(Precision pr) { return pr == Precision::Float ? "float" : "double"; }

// Reflected / direct figures of one station (reflection and reflection-layered share them).
json reflectionFigures(const ReflectionRow& row) {
  return {{"peak", row.peak},
          {"band_10_50_hz", row.band_10_50},
          {"band_10_20_hz", row.band_10_20},
          {"band_21_30_hz", row.band_21_30},
          {"band_31_40_hz", row.band_31_40},
          {"band_41_50_hz", row.band_41_50},
          {"band_21_35_hz", row.band_20_35},
          {"band_36_50_hz", row.band_35_50}};
}

// The absorber of a reflection run: the added strip and the boundary's own summary.
json absorberFields(const ReflectionCase& c) {
  return {{"layer_m", c.layer_m}, {"layer_bottom", c.bottom}, {"boundary", makeSoilBoundary(c.boundary)->summary()}};
}

void benchColumn(const BenchArgs& a, json& out) {
  for (Precision pr : a.precisions) {
    ColumnSpec spec;
    spec.precision = pr;
    const ColumnResult r = runColumn(spec);
    out[precisionName(pr)] = {{"expected_velocity_m_s", r.expected_velocity_m_s},
                              {"incident_velocity_m_s", r.incident_velocity_m_s},
                              {"velocity_error", r.velocity_error},
                              {"after_velocity_m_s", r.after_velocity_m_s},
                              {"step_reflection", r.step_reflection},
                              {"pulse_incident_peak_m_s", r.pulse_incident_peak_m_s},
                              {"pulse_reflected_peak_m_s", r.pulse_reflected_peak_m_s},
                              {"pulse_reflection", r.pulse_reflection},
                              {"dt_s", r.dt_s},
                              {"elements", r.elements}};
  }
}

void benchDamping(const BenchArgs& a, json& out) {
  // The Haren damping (soil_haren.yaml): beta = 4e-4 s on a velocity low-passed at 300 Hz.
  constexpr double kBetaS = 4e-4, kCutoffHz = 300.0;
  json rows = json::array();
  for (double f : {5.0, 10.0, 25.0, 50.0, 75.0, 100.0}) {
    const DampingDecayResult r = runDampingDecay(f, kBetaS, kCutoffHz, a.precisions.front());
    rows.push_back({{"frequency_hz", r.frequency_hz},
                    {"measured_ratio", r.measured_ratio},
                    {"target_ratio", r.target_ratio},
                    {"relative_error", r.measured_ratio / r.target_ratio - 1.0}});
  }
  out["beta_s"] = kBetaS;
  out["damping_cutoff_hz"] = kCutoffHz;
  out["modes"] = rows;
}

void benchThroughput(const BenchArgs& a, json& out) {
  ThroughputSpec spec;
  spec.nx = static_cast<size_t>(a.p.getInt("nx", 1, 1000));
  spec.ny = static_cast<size_t>(a.p.getInt("ny", 1, 1000));
  spec.nz = static_cast<size_t>(a.p.getInt("nz", 1, 1000));
  spec.steps = static_cast<int>(a.p.getInt("steps", 1, 10000000));
  spec.repeat = static_cast<int>(a.p.getInt("repeat", 1, 1000));
  spec.kernels.clear();
  std::stringstream kernels(a.p.get("kernel"));
  for (std::string item; std::getline(kernels, item, ',');) spec.kernels.push_back(kernelFromName(item));
  if (spec.kernels.empty()) throw ArgError("soil-bench: --kernel needs at least one kernel");
  const std::string first = kernelName(spec.kernels.front());
  std::ostringstream table;
  table << "precision kernel  threads | M el/s wall  per CPU s  per core | step ms  kernel ms  rest of step (CPU)"
        << " | kernel GFLOP/s  of peak | x " << first << " (step, kernel)\n";
  for (Precision pr : a.precisions) {
    const std::string pname = precisionName(pr);
    json jp;
    const std::vector<FmaPeak> peaks{measureFmaPeak(pr, 1), measureFmaPeak(pr, 2)};
    jp["fma_peak"] = {{"instruction_set", peaks[0].instruction_set},
                      {"gflop_s_1_thread", peaks[0].gflop_s},
                      {"gflop_s_2_threads", peaks[1].gflop_s}};
    std::vector<std::vector<ThroughputResult>> by_threads;
    for (int threads : {1, 2}) {
      spec.threads = threads;
      spec.precision = pr;
      by_threads.push_back(runThroughput(spec));
    }
    for (size_t q = 0; q < spec.kernels.size(); ++q) {
      json jk;
      for (size_t t = 0; t < by_threads.size(); ++t) {
        const ThroughputResult& r = by_threads[t][q];
        const double peak = peaks[t].gflop_s;
        jk["threads_" + std::to_string(r.threads)] = {
            {"median_element_updates_per_s", r.element_updates_per_s},
            {"per_core", r.element_updates_per_s / r.threads},
            {"median_per_cpu_second", r.element_updates_per_cpu_s},
            {"min", r.min_element_updates_per_s},
            {"max", r.max_element_updates_per_s},
            {"step_seconds", r.seconds_per_step},
            {"kernel_seconds", r.kernel_seconds_per_apply},
            {"rest_of_step_fraction", 1.0 - r.kernel_seconds_per_apply / r.seconds_per_step},
            {"cpu_seconds_per_step", r.cpu_seconds_per_step},
            {"kernel_cpu_seconds", r.kernel_cpu_seconds_per_apply},
            {"rest_of_step_fraction_cpu", 1.0 - r.kernel_cpu_seconds_per_apply / r.cpu_seconds_per_step},
            {"kernel_element_updates_per_s", r.kernel_element_updates_per_s},
            {"multiply_adds_per_step", r.multiply_adds_per_step},
            {"kernel_gflop_s", r.kernel_gflop_s},
            {"kernel_fraction_of_fma_peak", r.kernel_gflop_s / peak},
            {"step_ratio_to_" + first, r.step_ratio_to_first},
            {"kernel_ratio_to_" + first, r.kernel_ratio_to_first}};
        table << std::left << std::setw(10) << pname << std::setw(8) << kernelName(r.kernel) << std::setw(8)
              << r.threads << std::right << std::fixed << std::setprecision(1) << "| " << std::setw(11)
              << r.element_updates_per_s / 1e6 << std::setw(11) << r.element_updates_per_cpu_s / 1e6 << std::setw(10)
              << r.element_updates_per_s / 1e6 / r.threads << " | " << std::setprecision(2) << std::setw(7)
              << 1e3 * r.seconds_per_step << std::setw(11) << 1e3 * r.kernel_seconds_per_apply << std::setw(11)
              << std::setprecision(0) << 100.0 * (1.0 - r.kernel_seconds_per_apply / r.seconds_per_step) << " % ("
              << 100.0 * (1.0 - r.kernel_cpu_seconds_per_apply / r.cpu_seconds_per_step) << " % CPU)"
              << " | " << std::setprecision(1) << std::setw(14) << r.kernel_gflop_s << std::setw(7)
              << std::setprecision(0) << 100.0 * r.kernel_gflop_s / peak << " % | " << std::setprecision(2)
              << r.step_ratio_to_first << ", " << r.kernel_ratio_to_first << "\n";
      }
      const ThroughputResult &one = by_threads[0][q], &two = by_threads[1][q];
      jk["speedup_2_cores"] = two.element_updates_per_s / one.element_updates_per_s;
      jk["kernel_speedup_2_cores"] = one.kernel_seconds_per_apply / two.kernel_seconds_per_apply;
      table << std::left << std::setw(10) << pname << std::setw(8) << kernelName(one.kernel) << "2-core speed-up "
            << std::setprecision(2) << jk["speedup_2_cores"].get<double>() << " (kernel alone "
            << jk["kernel_speedup_2_cores"].get<double>() << ")\n"
            << std::right;
      jp[kernelName(one.kernel)] = jk;
    }
    table << pname << " FMA peak (" << peaks[0].instruction_set << "): " << std::setprecision(1) << peaks[0].gflop_s
          << " GFLOP/s 1 thread, " << peaks[1].gflop_s << " GFLOP/s 2 threads\n";
    out[pname] = jp;
  }
  // With --pml-thickness: the first kernel on the same mesh with the (first) PML case vs dashpots, 2 threads,
  // alternating rounds; the ratio says what the PML adds to a step.
  if (const std::vector<ReflectionCase> pml = a.pmlCases(); !pml.empty()) {
    ThroughputSpec one = spec;
    one.kernels = {spec.kernels.front()};
    one.threads = 2;
    one.precision = a.precisions.front();
    one.repeat = 1;
    std::vector<double> ratio, cpu_ratio;
    size_t layer_elements = 0;
    for (int rep = 0; rep < spec.repeat; ++rep) {
      one.boundary = BoundarySpec{};
      const ThroughputResult d = runThroughput(one).front();
      one.boundary = pml.front().boundary;
      const ThroughputResult m = runThroughput(one).front();
      ratio.push_back(m.seconds_per_step / d.seconds_per_step);
      cpu_ratio.push_back(d.element_updates_per_cpu_s / m.element_updates_per_cpu_s);
      layer_elements = m.boundary_elements;
    }
    auto med = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    out["pml"] = {{"boundary", absorberFields(pml.front())},
                  {"pml_elements", layer_elements},
                  {"step_time_ratio_pml_over_dashpots", med(ratio)},
                  {"cpu_time_ratio_pml_over_dashpots", med(cpu_ratio)}};
    table << "PML " << pml.front().boundary.pml.thickness_m << " m (" << layer_elements
          << " layer elements): step time x " << std::setprecision(2) << med(ratio) << " of dashpots\n";
  }
  out["elements"] = spec.nx * spec.ny * spec.nz;
  out["steps"] = spec.steps;
  out["repeat"] = spec.repeat;
  out["note"] =
      "medians over repeats, the kernels alternating within each repeat; ratios are medians of the ratios of the "
      "same repeat; the machine is shared, wall-clock figures are noisy; per_cpu_second = element updates per CPU "
      "second actually given to the process (user + sys over all threads); kernel_* = the kernel alone on the "
      "same mesh and box; rest_of_step = nodal update (and loads) = 1 - kernel / step; GFLOP/s count 2 flops "
      "per multiply-add; fma_peak from a register-only FMA loop in the widest vectors";
  // The table goes to stderr so that stdout stays one JSON document.
  std::cerr << table.str();
}

void benchReflection(const BenchArgs& a, json& out) {
  std::vector<ReflectionCase> cases{ReflectionCase{}};  // the small box, Lysmer only
  a.addLayerCases(cases);
  for (const ReflectionCase& c : a.pmlCases()) cases.push_back(c);
  const ReflectionResult r = runBoundaryReflection(a.p.getDouble("small-box", 1e-3, 1e3), cases);
  json rows = json::array();
  for (const ReflectionRow& row : r.rows) {
    json fields = absorberFields(row.absorber);
    fields.update(reflectionFigures(row));
    fields["elements"] = row.elements;
    fields["dt_s"] = row.dt_s;
    rows.push_back(fields);
  }
  out["r_m"] = r.r_m;
  out["window_s"] = r.window_s;
  out["reference_elements"] = r.reference_elements;
  out["runs"] = rows;
  out["note"] =
      "peak = max |w_small_box - w_reference_box| / max |w_reference| at r (Lamb Hann pulse, 50 ms); band_* = rms "
      "reflected / direct amplitude over 1 Hz lines of the band; the first run is the small box with Lysmer "
      "dashpots only, the others enlarge it by layer_m with the given boundary (a graded layer of alpha 0: the "
      "enlarged box with dashpots)";
}

void benchReflectionLayered(const BenchArgs& a, json& out) {
  const Config cfg = loadConfig(a.p);
  const SoilParams sp = loadSoilParams(cfg.root());
  LayeredReflectionSpec spec;
  spec.profile = sp.profile;
  spec.f_max_hz = sp.mesh.f_max_hz;
  spec.elements_per_wavelength = sp.mesh.elements_per_wavelength;
  spec.rayleigh_beta_s = sp.solver.rayleigh_beta_s;
  spec.damping_cutoff_hz = sp.solver.damping_cutoff_hz;
  spec.precision = sp.solver.precision;
  const std::vector<double> box = a.list("box");
  if (box.size() != 2) throw ArgError("soil-bench: --box needs half width,depth");
  spec.box_half_width_m = box[0];
  spec.box_depth_m = box[1];
  spec.reference_half_width_m = 3.0 * box[0];
  spec.reference_depth_m = 2.5 * box[1];
  // Until a Rayleigh wave at 200 m/s reflected by the reference side could reach the farthest station.
  spec.window_s = (2.0 * spec.reference_half_width_m - spec.distances_m.back()) / 200.0;
  std::vector<ReflectionCase> cases{ReflectionCase{}};
  const SolverOptions& so = sp.solver;
  if (so.boundary.method == BoundaryMethod::GradedLayer) {
    const GradedLayerSpec& g = so.boundary.graded_layer;
    cases.push_back(ReflectionCase::gradedLayer(g.thickness_m, g.max_alpha_1_s, g.exponent, g.bottom));
    cases.push_back(ReflectionCase::gradedLayer(g.thickness_m, 0.0, g.exponent, g.bottom));
  } else if (so.boundary.method == BoundaryMethod::Pml) {
    const PmlSpec& g = so.boundary.pml;
    cases.push_back(ReflectionCase::pml(g));
    cases.push_back(ReflectionCase::gradedLayer(g.thickness_m, 0.0, 1.0, g.bottom));
  }
  if (a.p.isSet("layer") || a.p.isSet("alpha") || a.p.isSet("exponent")) a.addLayerCases(cases);
  for (const ReflectionCase& c : a.pmlCases()) cases.push_back(c);
  const LayeredReflectionResult r = runLayeredReflection(spec, cases);
  json rows = json::array();
  for (const LayeredReflectionRow& row : r.rows) {
    json st = json::array();
    for (size_t k = 0; k < row.stations.size(); ++k) {
      json station = {{"r_m", spec.distances_m[k]}};
      station.update(reflectionFigures(row.stations[k]));
      st.push_back(station);
    }
    json fields = absorberFields(row.absorber);
    fields["elements"] = row.elements;
    fields["stations"] = st;
    rows.push_back(fields);
  }
  out["h_m"] = r.h_m;
  out["dt_s"] = r.dt_s;
  out["window_s"] = spec.window_s;
  out["box_m"] = box;
  out["reference_box_m"] = {spec.reference_half_width_m, spec.reference_depth_m};
  out["reference_elements"] = r.reference_elements;
  out["pulse_s"] = spec.pulse_s;
  out["runs"] = rows;
  out["note"] =
      "config's soil profile and mesh resolution, quarter model, Hann pulse point load; runs: box of interest with "
      "dashpots only, then (if configured) with the config's layer or PML outside it and the same enlarged box "
      "without it, then the --layer/--alpha/--exponent and --pml-* products if given; figures as in `reflection`";
}

void writeLambCsv(const std::string& path, const LambResult& r) {
  std::vector<std::string> cols{"t_s"};
  for (const auto& s : r.stations) {
    cols.push_back("w_fe_r" + std::to_string(s.r_m) + "_m");
    cols.push_back("w_analytic_r" + std::to_string(s.r_m) + "_m");
  }
  io::CsvWriter csv(path, cols);
  for (size_t i = 0; i < r.t_s.size(); ++i) {
    std::vector<double> row{r.t_s[i]};
    for (size_t k = 0; k < r.stations.size(); ++k) {
      row.push_back(r.w_fe[k][i]);
      row.push_back(r.w_an[k][i]);
    }
    csv.row(row);
  }
  csv.commit();
}

void benchLamb(const BenchArgs& a, json& out) {
  LambSpec spec;
  spec.precision = a.precisions.front();
  if (a.p.has("lamb-h") && !a.p.get("lamb-h").empty()) spec.h_m = a.p.getDouble("lamb-h", 1e-3, 1e3);
  const LambResult r = runLamb(spec);
  json st = json::array();
  for (const auto& s : r.stations) {
    st.push_back({{"r_m", s.r_m},
                  {"t_p_fe_s", s.t_p_fe_s},
                  {"t_p_analytic_s", s.t_p_an_s},
                  {"t_p_error", s.t_p_fe_s / s.t_p_an_s - 1.0},
                  {"t_rayleigh_peak_fe_s", s.t_r_fe_s},
                  {"t_rayleigh_peak_analytic_s", s.t_r_an_s},
                  {"t_rayleigh_error", s.t_r_fe_s / s.t_r_an_s - 1.0},
                  {"peak_fe_m", s.peak_fe_m},
                  {"peak_analytic_m", s.peak_an_m},
                  {"peak_error", s.peak_fe_m / s.peak_an_m - 1.0},
                  {"elements_per_rayleigh_wavelength", s.elements_per_rayleigh_wavelength}});
  }
  out["stations"] = st;
  out["elements"] = r.elements;
  out["dt_s"] = r.dt_s;
  out["material"] = {{"vs_m_s", spec.material.vs()},
                     {"vp_m_s", spec.material.vp()},
                     {"vr_m_s", spec.material.vr()},
                     {"poisson_ratio", spec.material.poisson_ratio}};
  out["h_m"] = spec.h_m;
  out["rise_s"] = spec.rise_s;
  if (a.p.has("csv") && !a.p.get("csv").empty()) writeLambCsv(a.p.get("csv"), r);
}

// Strong scaling over MPI ranks on the configured (Haren) mesh: run under mpirun -np N (docs/soil.md,
// "MPI ranks"). Rank 0 prints; the table goes to stderr.
void benchRanks(const BenchArgs& a, json& out) {
  const std::shared_ptr<SoilComm> comm = worldSoilComm();
  const Config cfg = loadConfig(a.p);
  const SoilParams sp = loadSoilParams(cfg.root());
  RankScalingSpec spec;
  spec.mesh = buildMesh(sp.profile, sp.mesh);
  spec.options = sp.solver;
  spec.options.threads = static_cast<int>(a.p.getInt("rank-threads", 0, 1024));
  if (spec.options.threads < 1) throw ArgError("soil-bench: --rank-threads must be at least 1");
  spec.options.precision = a.precisions.front();
  spec.steps = static_cast<int>(a.p.getInt("steps", 1, 10000000));
  spec.repeat = static_cast<int>(a.p.getInt("repeat", 1, 1000));
  const RankScalingResult r = runRankScaling(spec, comm);
  const StructuredMesh& m = spec.mesh;
  out["config"] = cfg.file();
  out["mesh"] = {{"nx", m.nx}, {"ny", m.ny}, {"nz", m.nz}, {"elements", r.elements}};
  out["ranks"] = r.ranks;
  out["threads_per_rank"] = spec.options.threads;
  out["kernel"] = kernelName(spec.options.kernel);
  out["boundary"] = boundaryMethodName(spec.options.boundary.method);
  out["precision"] = precisionName(spec.options.precision);
  out["slab_cuts"] = r.cuts;
  out["one_rank_step_s"] = r.one_rank_step_s;
  out["spread_step_s"] = r.spread_step_s;
  out["speedup"] = r.speedup;
  out["speedup_min_max"] = {r.min_speedup, r.max_speedup};
  out["parallel_efficiency"] = r.speedup / r.ranks;
  out["halo_bytes_per_step_per_rank"] = r.halo_bytes_per_step;
  out["halo_wait_fraction_per_rank"] = r.halo_wait_fraction;
  out["one_rank_seconds_per_element_step"] = r.one_rank_seconds_per_element_step;
  out["slabs_alone_step_s"] = r.alone_step_s;
  out["ceiling_speedup"] = r.ceiling_speedup;
  out["slab_alone_step_s_per_rank"] = r.slab_alone_step_s;
  out["steps"] = spec.steps;
  out["repeat"] = spec.repeat;
  out["note"] =
      "medians over repeats; each repeat times the whole mesh on rank 0 alone (the other ranks sleep), then the "
      "mesh over all ranks (rank 0's wall clock between barriers); speedup = median of the repeats' ratios; "
      "halo bytes = the shared node planes' forces sent per step; wait fraction = time in the halo wait / step; "
      "ceiling = one rank / each slab run as a mesh of its own on all ranks at once (no exchange)";
  if (!comm->root()) return;
  std::ostringstream t;
  t << std::fixed << std::setprecision(3) << "soil ranks: mesh " << m.nx << " x " << m.ny << " x " << m.nz << " = "
    << r.elements << " elements, " << r.ranks << " ranks x " << spec.options.threads << " thread(s), "
    << kernelName(spec.options.kernel) << " kernel, " << boundaryMethodName(spec.options.boundary.method) << "\n"
    << "  one rank " << 1e3 * r.one_rank_step_s << " ms/step, " << r.ranks << " ranks " << 1e3 * r.spread_step_s
    << " ms/step: speed-up " << std::setprecision(2) << r.speedup << " (min " << r.min_speedup << ", max "
    << r.max_speedup << "), efficiency " << r.speedup / r.ranks << "\n";
  if (r.ranks > 1) {
    t << "  the slabs alone (each a mesh of its own, all ranks at once, no exchange) " << std::setprecision(3)
      << 1e3 * r.alone_step_s << " ms/step: the machine's ceiling " << std::setprecision(2) << r.ceiling_speedup
      << "; spread / ceiling " << r.speedup / r.ceiling_speedup << "\n";
  }
  for (size_t q = 0; q < r.halo_bytes_per_step.size(); ++q) {
    t << "  rank " << q << ": element columns [" << r.cuts[q] << ", " << r.cuts[q + 1] << "), halo "
      << std::setprecision(1) << r.halo_bytes_per_step[q] / 1e3 << " kB sent per step, waiting "
      << 100.0 * r.halo_wait_fraction[q] << " % of the step";
    if (q < r.slab_alone_step_s.size())
      t << ", slab alone " << std::setprecision(3) << 1e3 * r.slab_alone_step_s[q] << " ms/step";
    t << "\n";
  }
  std::cerr << t.str();
}

// The cost of the configured inclusions (e.g. --set 'soil.inclusions=[{name: trench, ...}]'): the same
// mesh and solver without and with them, stepped alternately; per step and per simulated second (a stiff
// inclusion lowers the stable step).
void benchInclusions(const BenchArgs& a, json& out) {
  const Config cfg = loadConfig(a.p);
  const SoilParams sp = loadSoilParams(cfg.root());
  if (sp.mesh.inclusions.empty()) {
    throw ArgError(
        "soil-bench inclusions: the configuration has no soil.inclusions; give them with --set "
        "'soil.inclusions=[{name: trench, kind: void, x_m: [-15, 15], y_m: [3, 4], depth_m: [0, 4]}]'");
  }
  const int steps = static_cast<int>(a.p.getInt("steps", 1, 10000000)),
            repeat = static_cast<int>(a.p.getInt("repeat", 1, 1000));
  if (steps < 1 || steps > 100000 || repeat < 1 || repeat > 1000) {
    throw ArgError("soil-bench inclusions: --steps in [1, 100000], --repeat in [1, 1000]");
  }
  MeshSpec plain = sp.mesh;
  plain.inclusions.clear();
  Solver without(buildMesh(sp.profile, plain), sp.solver);
  Solver with(buildMesh(sp.profile, sp.mesh), sp.solver);
  auto timeSteps = [steps](Solver& s) {
    const auto t0 = std::chrono::steady_clock::now();
    s.run(static_cast<uint64_t>(steps));
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / steps;
  };
  timeSteps(without), timeSteps(with);  // warm up
  std::vector<double> t_without, t_with, ratio;
  for (int r = 0; r < repeat; ++r) {
    // Alternate the order: a drift of the machine's speed falls on both.
    double tw = 0.0, ti = 0.0;
    if (r % 2 == 0) {
      tw = timeSteps(without), ti = timeSteps(with);
    } else {
      ti = timeSteps(with), tw = timeSteps(without);
    }
    t_without.push_back(tw), t_with.push_back(ti), ratio.push_back(ti / tw);
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const StructuredMesh& m = with.mesh();
  size_t elements = 0;
  for (const MeshInclusion& inc : m.inclusions) elements += inc.elements.count();
  const double step_ratio = median(ratio);
  out["config"] = cfg.file();
  out["mesh"] = {{"nx", m.nx}, {"ny", m.ny}, {"nz", m.nz}, {"elements", m.elementCount()}};
  out["inclusions"] = inclusionsSummary(m);
  out["inclusion_elements"] = elements;
  out["kernel"] = kernelName(sp.solver.kernel);
  out["precision"] = precisionName(sp.solver.precision);
  out["dt_without_s"] = without.dt();
  out["dt_with_s"] = with.dt();
  out["step_s_without_median"] = median(t_without);
  out["step_s_with_median"] = median(t_with);
  out["step_ratio_median"] = step_ratio;
  out["step_ratio_min_max"] = {*std::min_element(ratio.begin(), ratio.end()),
                               *std::max_element(ratio.begin(), ratio.end())};
  out["simulated_second_ratio"] = step_ratio * without.dt() / with.dt();
  out["steps"] = steps;
  out["repeat"] = repeat;
  out["note"] =
      "per-step wall time of the same mesh and solver without and with the inclusions, stepped alternately; "
      "ratio = median of the repeats' ratios; per simulated second also counts the change of the stable step";
}

// Passive isolation by a trench or a wall on a homogeneous half-space (soil/screening.hpp): the amplitude
// reduction ratio behind it per normalised depth, against the published field tests and charts.
void benchTrench(const BenchArgs& a, json& out) {
  ScreeningSpec spec = defaultScreeningSpec();
  spec.element_m = a.p.getDouble("screen-element", 1e-3, 10.0);
  if (!(spec.element_m >= 0.05 && spec.element_m <= 0.5))
    throw ArgError("soil-bench: --screen-element in [0.05, 0.5] m");
  spec.zone_start_wavelengths = a.p.getDouble("screen-zone-start", 0.0, 100.0);
  if (!(spec.zone_start_wavelengths >= 0.0 && spec.zone_start_wavelengths <= 3.0)) {
    throw ArgError("soil-bench: --screen-zone-start in [0, 3] Rayleigh wavelengths");
  }
  const double f_min = a.p.getDouble("screen-f-min", 1e-3, 1e4);
  const double f_max = a.p.getDouble("screen-f-max", 1e-3, 1e4);
  if (!(f_min >= 25.0 && f_max <= 90.0 && f_min <= f_max)) {
    throw ArgError("soil-bench: --screen-f-min <= --screen-f-max, both in [25, 90] Hz");
  }
  spec.frequencies_hz.erase(std::remove_if(spec.frequencies_hz.begin(), spec.frequencies_hz.end(),
                                           [f_min, f_max](double f) { return f > f_max + 1e-9 || f < f_min - 1e-9; }),
                            spec.frequencies_hz.end());
  spec.precision = a.precisions.front();
  spec.threads = 0;
  const std::string fills = a.p.get("screen-fills");
  std::stringstream list(fills);
  for (std::string item; std::getline(list, item, ',');) {
    // In-fills 1.5 m deep: a soft one (EPS geofoam, [assumed] E 8 MPa, rho 20, nu 0.1: impedance 0.047 x the
    // soil's) and a stiff wall (jet grout, [assumed] E 3 GPa, rho 2000, nu 0.2: 13 x).
    if (item == "soft") {
      spec.barriers.push_back({"soft fill 1.5 m", false, {8.0e6, 20.0, 0.1}, 1.5});
    } else if (item == "stiff") {
      spec.barriers.push_back({"stiff wall 1.5 m", false, {3.0e9, 2000.0, 0.2}, 1.5});
    } else if (!item.empty() && item != "none") {
      throw ArgError("soil-bench: --screen-fills takes soft, stiff or none, comma-separated (got '" + item + "')");
    }
  }
  const ScreeningResult r = runScreening(spec);
  out["rayleigh_speed_m_s"] = r.rayleigh_speed_m_s;
  out["soil"] = {{"vs_m_s", spec.soil.vs()}, {"vp_m_s", spec.soil.vp()}, {"poisson_ratio", spec.soil.poisson_ratio}};
  out["elements"] = r.elements;
  out["element_m"] = spec.element_m;
  out["zone_nodes"] = r.zone_nodes;
  out["frequencies_hz"] = r.frequencies_hz;
  out["reference_run_s"] = r.reference_seconds;
  out["geometry_m"] = {{"source_to_barrier", spec.barrier_x_m},
                       {"barrier_width", spec.barrier_width_m},
                       {"barrier_length", 2.0 * spec.barrier_half_length_m},
                       {"zone_start_rayleigh_wavelengths", spec.zone_start_wavelengths},
                       {"zone_length_rayleigh_wavelengths", spec.zone_length_wavelengths},
                       {"zone_half_width_rayleigh_wavelengths", spec.zone_half_width_wavelengths}};
  json curves = json::array();
  std::ostringstream t;
  t << std::fixed << std::setprecision(2);
  for (const ScreeningCurve& c : r.curves) {
    curves.push_back({{"name", c.name},
                      {"depth_m", c.depth_m},
                      {"dt_s", c.dt_s},
                      {"run_s", c.seconds},
                      {"normalised_depth", c.normalised_depth},
                      {"amplitude_ratio", c.amplitude_ratio}});
    t << c.name << " (dt " << std::setprecision(6) << c.dt_s << " s, " << std::setprecision(1) << c.seconds
      << " s):\n  D/lambda_R";
    t << std::setprecision(2);
    for (double d : c.normalised_depth) t << " " << std::setw(5) << d;
    t << "\n  A_r       ";
    for (double v : c.amplitude_ratio) t << " " << std::setw(5) << v;
    t << "\n";
  }
  out["curves"] = curves;
  out["note"] =
      "A_r = mean over the zone's surface nodes of |U_z with barrier (f)| / |U_z without (f)| (Woods 1968); "
      "D / lambda_R = depth x f / c_R; half model (symmetry plane through the source), PML on the other faces";
  std::cerr << t.str();
}

// A box with an open pit and a concrete block, run here and by CalculiX (ccx, an independent explicit
// finite element code): the voids' free faces and the inclusions' material against a code that meshes
// them by leaving elements out (soil/calculix_peer.hpp).
void benchVoidPeer(const BenchArgs& a, json& out) {
  PeerCase c = voidPeerCase();
  c.duration_s = a.p.getDouble("peer-duration", 1e-5, 10.0);
  if (!(c.duration_s >= 10.0 * c.dt_s && c.duration_s <= 1.0)) {
    throw ArgError("soil-bench: --peer-duration must lie in [1e-4, 1] s");
  }
  namespace fs = std::filesystem;
  const std::string keep = a.p.has("peer-dir") ? a.p.get("peer-dir") : "";
  const fs::path dir =
      keep.empty() ? fs::temp_directory_path() / ("railvib_void_peer_" + std::to_string(::getpid())) : fs::path(keep);
  fs::create_directories(dir);
  {
    std::ofstream inp(dir / "peer.inp");
    inp << calculixInput(c);
    if (!inp) throw std::runtime_error("soil-bench void-peer: cannot write " + (dir / "peer.inp").string());
  }
  const std::string ccx = a.p.get("ccx");
  const std::string command = "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 '" + ccx + "' -i peer > ccx.log 2>&1";
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  const double ccx_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (status != 0) {
    throw std::runtime_error("soil-bench void-peer: CalculiX (" + ccx + ") failed with status " +
                             std::to_string(status) +
                             "; is it installed (apt-get install calculix-ccx)? log: " + (dir / "ccx.log").string());
  }
  std::ifstream dat(dir / "peer.dat");
  const std::string text((std::istreambuf_iterator<char>(dat)), std::istreambuf_iterator<char>());
  const PeerHistory peer = readCalculixDisplacements(text, c);
  const auto t1 = std::chrono::steady_clock::now();
  const PeerHistory own = runPeerCase(c);
  const double own_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  const size_t nodes = c.output_nodes.size();
  json per_node = json::array();
  for (size_t q = 0; q < nodes; ++q) {
    PeerHistory a1, b1;
    for (size_t t = 0; t < own.time_s.size(); ++t) {
      a1.time_s.push_back(own.time_s[t]);
      b1.time_s.push_back(peer.time_s[t]);
      for (int d = 0; d < 3; ++d) {
        a1.u_m.push_back(own.u_m[(t * nodes + q) * 3 + d]);
        b1.u_m.push_back(peer.u_m[(t * nodes + q) * 3 + d]);
      }
    }
    const size_t nd = c.output_nodes[q], sx = c.mesh.nx + 1, sxy = sx * (c.mesh.ny + 1);
    per_node.push_back(
        {{"node_ijk", {nd % sx, (nd % sxy) / sx, nd / sxy}}, {"difference_over_node_peak", peerDifference(a1, b1)}});
  }
  out["difference_over_peak"] = peerDifference(own, peer);
  // What the comparison can see: railvib's run of the same box without its pit and block.
  PeerCase plain = c;
  plain.mesh.inclusions.clear();
  out["difference_over_peak_without_inclusions"] = peerDifference(runPeerCase(plain), peer);
  out["nodes"] = per_node;
  out["elements"] = c.mesh.elementCount();
  out["inclusions"] = c.mesh.inclusions.size();
  out["dt_s"] = c.dt_s;
  out["steps"] = static_cast<size_t>(std::llround(c.duration_s / c.dt_s));
  out["ccx_s"] = ccx_s;
  out["railvib_s"] = own_s;
  out["peer_dir"] = dir.string();
  out["note"] =
      "per output node max |u_railvib - u_calculix| / max |u_calculix| over its displacement history (x, y, depth), "
      "the largest over the nodes; "
      "CalculiX C3D8, *DYNAMIC EXPLICIT ALPHA=0, the same fixed increment and load polyline";
  if (keep.empty()) fs::remove_all(dir);
}

struct BenchCase {
  const char* name;
  void (*run)(const BenchArgs&, json&);
};
const BenchCase kBenchCases[] = {
    {"ranks", benchRanks},
    {"column", benchColumn},
    {"damping", benchDamping},
    {"throughput", benchThroughput},
    {"lamb", benchLamb},
    {"reflection", benchReflection},
    {"reflection-layered", benchReflectionLayered},
    {"void-peer", benchVoidPeer},
    {"inclusions", benchInclusions},
    {"trench", benchTrench},
};

std::string benchCaseList() {
  std::string names;
  for (const BenchCase& c : kBenchCases) names += (names.empty() ? "" : " | ") + std::string(c.name);
  return names;
}

std::vector<Precision> benchPrecisions(const std::string& prec) {
  std::vector<Precision> precisions;
  if (prec == "float" || prec == "both") precisions.push_back(Precision::Float);
  if (prec == "double" || prec == "both") precisions.push_back(Precision::Double);
  if (precisions.empty()) throw ArgError("soil-bench: --precision must be float, double or both");
  return precisions;
}

int soilBench(const std::vector<std::string>& args) {
  ArgParser p("soil-bench", "soil verification and benchmarks: " + benchCaseList());
  p.option("case", benchCaseList() + " (or give it as first argument)", "");
  p.option("nx", "throughput: elements along x", "160");
  p.option("ny", "throughput: elements along y", "80");
  p.option("nz", "throughput: elements in depth", "30");
  p.option("steps", "throughput: steps per measurement", "20");
  p.option("repeat", "throughput: measurements (median reported)", "5");
  p.option("kernel", "throughput: stiffness kernels side by side, comma-separated (element | stencil)",
           "element,stencil");
  p.option("precision", "float | double | both (ranks: the first)", "both");
  p.option("rank-threads", "ranks: OpenMP threads per rank", "1");
  p.option("small-box", "reflection: half width and depth of the small box (m)", "8");
  p.option("layer", "reflection: absorbing layer thicknesses (m), comma-separated", "4");
  p.option("alpha", "reflection: layer alpha at the outer face (1/s), comma-separated; 0 = enlarged box, no layer",
           "0,60");
  p.option("layer-bottom", "reflection: 1 = layer along the bottom too (box deepens), 0 = sides only", "0");
  p.option("exponent", "reflection: exponents n of the layer profile (s/L)^n, comma-separated", "1");
  p.option("lamb-h", "lamb: element size (m)", "");
  p.option("csv", "lamb: write FE and analytic curves to this CSV", "");
  p.option("box", "reflection-layered: half width and depth of the box of interest (m), e.g. 16,12", "16,12");
  // PML cases of `reflection`, `reflection-layered` and `throughput`: the product of these lists.
  p.option("pml-thickness", "reflection*, throughput: PML thicknesses (m), comma-separated (none if empty)", "");
  p.option("pml-reflection", "reflection*: PML target reflection coefficients R, comma-separated", "1e-3");
  p.option("pml-exponent", "reflection*: PML profile exponents n, comma-separated", "2");
  p.option("pml-kappa", "reflection*: PML kappa at the outer face, comma-separated", "1");
  p.option("pml-alpha", "reflection*: PML CFS frequency shift alpha (1/s), comma-separated", "0");
  p.option("pml-ratio", "reflection*: M-PML ratio p, comma-separated", "0");
  p.option("pml-bottom", "reflection*: 1 = PML along the bottom too, 0 = sides only", "1");
  p.option("pml-outer-dashpots", "reflection*: 1 = dashpots at the PML's outer faces, 0 = free faces", "1");
  p.option("ccx", "void-peer: the CalculiX executable", "ccx");
  p.option("screen-element", "trench: element size (m)", "0.125");
  p.option("screen-f-min", "trench: lowest frequency read (Hz; 25-90)", "25");
  p.option("screen-f-max", "trench: highest frequency read (Hz; 25-90)", "90");
  p.option("screen-zone-start", "trench: the zone's start behind the barrier (Rayleigh wavelengths)", "0");
  p.option("screen-fills", "trench: in-filled barriers beside the open trenches: soft, stiff, none (comma-separated)",
           "soft,stiff");
  p.option("peer-duration", "void-peer: simulated time (s)", "0.04");
  p.option("peer-dir", "void-peer: keep the CalculiX deck and results in this folder (default: a temporary one)", "");
  p.flag("json", "JSON only on stdout (the default prints JSON too)");
  addConfigOptions(p);  // reflection-layered: soil profile, mesh resolution, damping and layer from the config
  std::string which;
  if (!parseWithCase(p, args, which)) return 0;
  const BenchArgs bench{p, benchPrecisions(p.get("precision"))};
  for (const BenchCase& c : kBenchCases) {
    if (which != c.name) continue;
    json out;
    out["case"] = which;
    c.run(bench, out);
    if (worldSoilComm()->root()) printJson(out);  // under mpirun (case ranks): rank 0 prints
    return 0;
  }
  throw ArgError("soil-bench: unknown case '" + which + "' (" + benchCaseList() + ")");
}

double peakRssGb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1e6;  // kB -> GB
  }
  return 0.0;
}

int soilRun(const std::vector<std::string>& args) {
  ArgParser p("soil", "offline 3D soil run: sleeper loads CSV in, receiver velocities + surface snapshots out");
  addConfigOptions(p);
  p.option("loads",
           "soil loads CSV (t_s, then a column per sleeper, N, downward +, both rails; or, from a full-width "
           "passage, x_<position>_left and x_<position>_right per sleeper: each rail seat's force), e.g. passage "
           "soil_loads.csv");
  p.option("sleepers",
           "sleeper positions CSV (sleeper, x_m); default: sleepers.csv next to --loads, else the "
           "track config rule",
           "auto");
  p.option("out", "output directory");
  p.option("duration", "simulated time (s); 0 = simulation.duration_s", "0");
  if (!p.parse(args)) return 0;
  if (!p.has("loads") || p.get("loads").empty()) throw ArgError("soil: --loads is required");
  if (!p.has("out") || p.get("out").empty()) throw ArgError("soil: --out is required");
  const Config cfg = loadConfig(p);
  const ConfigNode root = cfg.root();
  // The house's free-field receivers, as the soil node has them (its footprint is the building's input).
  SoilParams params = loadSoilParams(root, coupling::houseReceivers(root, false));
  const double duration = p.getDouble("duration", 0.0, 3600.0) <= 0.0 ? vehicle::loadPassageParams(root).duration_s
                                                                      : p.getDouble("duration", 0.0, 3600.0);

  const io::CsvTable loads = io::readCsv(p.get("loads"));
  if (loads.columns.size() < 2 || loads.columns[0] != "t_s" || loads.rows.size() < 2) {
    throw std::runtime_error(p.get("loads") + ": expected columns t_s, sleeper_0, ... and at least 2 rows");
  }
  // Every row: uniform time steps from t = 0, every force finite and within limits.soil_load_n.
  const double rate = 1.0 / io::uniformStep(loads, 0);
  if (std::abs(loads.rows[0][0]) > 1e-9)
    throw std::runtime_error(loads.where(0) + ": the first sample must be at t = 0");
  const StreamLimits limits = loadStreamLimits(root);
  for (size_t i = 0; i < loads.rows.size(); ++i) {
    const auto& row = loads.rows[i];
    const size_t bad = firstValueOutside(row.data() + 1, row.size() - 1, limits.soil_load_n);
    if (bad < row.size() - 1) {
      throw std::runtime_error(loads.where(i) + ": column '" + loads.columns[bad + 1] +
                               "' = " + formatValue(row[bad + 1]) + " N: beyond the " +
                               formatValue(limits.soil_load_n) + " N a sleeper load may be (limits.soil_load_n)");
    }
  }
  // A full-width passage gives each rail seat's force: a pair of columns per sleeper (railColumn).
  const std::string left_tail = railColumn("", track::Rail::Left);
  auto baseOfLeft = [&](const std::string& column) -> std::optional<std::string> {
    if (column.size() < left_tail.size() ||
        column.compare(column.size() - left_tail.size(), left_tail.size(), left_tail))
      return std::nullopt;
    return column.substr(0, column.size() - left_tail.size());
  };
  const size_t seats = baseOfLeft(loads.columns[1]) ? 2 : 1;
  for (size_t c = 1; seats == 2 && c < loads.columns.size(); c += 2) {
    const std::optional<std::string> base = baseOfLeft(loads.columns[c]);
    if (!base || c + 1 >= loads.columns.size() || loads.columns[c + 1] != railColumn(*base, track::Rail::Right)) {
      throw std::runtime_error(p.get("loads") + ": column " + std::to_string(c + 1) + " '" + loads.columns[c] +
                               "': rail seat columns come in pairs <sleeper>_left, <sleeper>_right");
    }
  }
  const size_t ns = (loads.columns.size() - 1) / seats;
  // The rail seats of the scenario's track (none for the half track): the columns must be its.
  const std::vector<double> seat_y = track::soilRailSeatPositions(track::loadTrackParams(root));
  if (std::max<size_t>(1, seat_y.size()) != seats) {
    throw std::runtime_error(p.get("loads") + ": " +
                             (seats == 2 ? std::string("a force per rail seat (x_<position>_left/_right columns)")
                                         : std::string("one force per sleeper (x_<position> columns)")) +
                             ", but the scenario's track.width is " + (seat_y.empty() ? "half" : "full") +
                             ": run soil with the track.width of the passage that wrote the loads");
  }
  std::vector<double> sleeper_x;
  std::string sleeper_file = p.get("sleepers") == "auto" ? "" : p.get("sleepers");
  if (sleeper_file.empty()) {
    const auto sib = std::filesystem::path(p.get("loads")).parent_path() / "sleepers.csv";
    if (std::filesystem::exists(sib)) sleeper_file = sib.string();
  }
  if (!sleeper_file.empty()) {
    const io::CsvTable sl = io::readCsv(sleeper_file);
    const size_t cx = sl.column("x_m");
    for (size_t i = 0; i < sl.rows.size(); ++i) {
      const double x = sl.rows[i][cx];
      if (!sleeper_x.empty() && !(x > sleeper_x.back())) {
        throw std::runtime_error(sl.where(i) + ": x_m = " + formatValue(x) +
                                 ": sleeper positions must increase (previous " + formatValue(sleeper_x.back()) + ")");
      }
      sleeper_x.push_back(x);
    }
  } else {
    sleeper_x = params.track.sleeperPositions();
  }
  if (sleeper_x.size() != ns) {
    throw std::runtime_error(p.get("loads") + ": " + std::to_string(ns) + " sleeper columns but " +
                             std::to_string(sleeper_x.size()) + " sleeper positions");
  }
  // A column named after its sleeper's position (x_<m>, as passage and moving-load write them) must be
  // that sleeper's: loads of another track layout would land on the wrong sleepers.
  for (size_t s = 0; s < ns; ++s) {
    const std::string& column = loads.columns[1 + s * seats];
    const std::string base = seats == 2 ? baseOfLeft(column).value_or(column) : column;
    if (base.rfind("x_", 0) != 0) continue;
    char* end = nullptr;
    const double x = std::strtod(base.c_str() + 2, &end);
    if (end == base.c_str() + 2 || *end != '\0' || !std::isfinite(x)) continue;
    if (std::abs(x - sleeper_x[s]) > std::max(1e-3, 1e-5 * std::abs(x))) {
      throw std::runtime_error(p.get("loads") + ": column " + std::to_string(2 + s * seats) + " '" + column +
                               "' is the load of a sleeper at x = " + formatValue(x) + " m, but sleeper " +
                               std::to_string(s) + " of the scenario lies at x = " + formatValue(sleeper_x[s]) +
                               " m: the loads come from another track layout");
    }
  }
  // The loads must carry every frequency the mesh resolves (the same rule as track.output.load_sample_rate_hz).
  if (rate < 2.0 * params.mesh.f_max_hz) {
    throw std::runtime_error(p.get("loads") + ": sampled at " + formatValue(rate) +
                             " Hz, below twice soil.mesh.f_max_hz (" + formatValue(params.mesh.f_max_hz) +
                             " Hz): the loads cannot drive the frequencies the mesh resolves");
  }
  // Under mpirun every rank runs this command with the same arguments (it reads the same inputs: on
  // several hosts they must be readable on each) and holds a slab of the mesh; rank 0 alone writes.
  const std::shared_ptr<SoilComm> comm = worldSoilComm();
  const bool is_root = comm->root();
  const std::string dir = p.get("out");
  if (is_root) std::filesystem::create_directories(dir);

  const auto wall0 = std::chrono::steady_clock::now();
  // building.coupling: two_way puts the house's foundation (a rigid body carrying the reduced house) in the soil.
  SoilModel model(params, sleeper_x, seat_y, rate, coupling::attachHouse(cfg.root(), params), comm);
  nlohmann::json summary = model.summary();
  summary["loads_per_sleeper"] = model.loadsPerSleeper();
  // Each rank's memory; the summary reports the largest.
  summary["memory_bytes"] = comm->maximum(summary["memory_bytes"].get<double>());
  if (is_root)
    std::cerr << "soil: mesh " << summary["nx"] << " x " << summary["ny"] << " x " << summary["nz"] << " = "
              << summary["elements"] << " elements, " << summary["dofs"] << " DOFs, dt = " << model.dt()
              << " s (undamped limit " << summary["dt_undamped_limit_s"] << ", naive Rayleigh limit "
              << summary["dt_naive_rayleigh_limit_s"] << "), memory " << summary["memory_bytes"].get<double>() / 1e9
              << " GB\n";
  if (is_root && comm->size() > 1) std::cerr << "soil: " << summary["partition"].get<std::string>() << "\n";
  for (const auto& l : is_root ? summary["layers"] : nlohmann::json::array()) {
    std::cerr << "  layer " << l["top_m"] << "-" << l["bottom_m"] << " m: " << l["levels"] << " levels of " << l["dz_m"]
              << " m, Vs " << l["vs_m_s"] << " m/s, resolved up to " << l["resolved_hz"] << " Hz\n";
  }
  if (is_root && !model.droppedSleepers().empty()) std::cerr << "soil: " << model.droppedLoadsNote() << "\n";
  std::vector<double> frame;
  frame.reserve(loads.rows.size() * ns * seats);
  for (const auto& r : loads.rows) frame.insert(frame.end(), r.begin() + 1, r.end());
  model.pushLoads(0, frame.data(), loads.rows.size());
  model.finishLoads();

  std::vector<std::string> cols{"t_s"};
  for (const auto& r : model.receivers()) {
    for (const char* c : {"_vx_m_s", "_vy_m_s", "_vz_m_s"}) cols.push_back(r.name + c);
  }
  std::optional<io::CsvWriter> rcsv;
  if (is_root) rcsv.emplace(dir + "/receivers.csv", cols);
  std::vector<SurfaceSnapshot> snaps;
  std::vector<SectionSnapshot> sections;
  ReceiverBlock block;
  std::vector<double> peak(model.receivers().size(), 0.0), tpeak(model.receivers().size(), 0.0);
  auto drain = [&]() {
    model.takeReceiverSamples(block);  // collective: complete on rank 0
    model.takeSnapshots(snaps);
    model.takeSectionSnapshots(sections);
    if (!is_root) {
      snaps.clear();
      sections.clear();
      return;
    }
    const size_t nr = block.names.size();
    for (size_t f = 0; f < block.frames(); ++f) {
      std::vector<double> row{static_cast<double>(block.first_index + f) / block.rate_hz};
      for (size_t q = 0; q < 3 * nr; ++q) row.push_back(block.velocity_m_s[f * 3 * nr + q]);
      for (size_t r = 0; r < nr; ++r) {
        const double vz = std::abs(block.velocity_m_s[f * 3 * nr + 3 * r + 2]);
        if (vz > peak[r]) {
          peak[r] = vz;
          tpeak[r] = row[0];
        }
      }
      rcsv->row(row);
    }
  };
  const double chunk = 0.05;
  double next_report = 0.0;
  const auto t_step0 = std::chrono::steady_clock::now();
  model.finishRun(duration, chunk, [&] {
    drain();
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_step0).count();
    if (is_root && (el >= next_report || model.time() >= duration - 1e-12)) {
      const double frac = std::min(1.0, model.time() / duration);
      std::cerr << "soil: t = " << model.time() << " / " << duration << " s (" << std::round(1000 * frac) / 10
                << " %), elapsed " << std::round(el) << " s, ETA " << std::round(el * (1 - frac) / std::max(frac, 1e-9))
                << " s\n";
      next_report = el + 10.0;
    }
    return true;
  });
  drain();
  const double rss_gb = comm->maximum(peakRssGb());
  double cpu_s = 0.0;
  {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    cpu_s = u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
    comm->sumToRoot(&cpu_s, 1);
  }
  if (!is_root) return 0;
  rcsv->commit();
  writeSnapshots(dir + "/surface_vz.snap", snaps);
  if (!sections.empty()) writeSectionSnapshots(dir + "/section_vz.snap", sections);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double step_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_step0).count();
  nlohmann::json peaks = nlohmann::json::object();
  for (size_t r = 0; r < model.receivers().size(); ++r) {
    peaks[model.receivers()[r].name] = {{"peak_abs_vz_m_s", peak[r]}, {"t_peak_s", tpeak[r]}};
  }
  summary["duration_s"] = duration;
  summary["steps"] = model.solver().stepCount();
  summary["wall_s"] = wall;
  summary["stepping_wall_s"] = step_wall;
  summary["element_updates_per_s"] = static_cast<double>(model.solver().stepCount()) *
                                     static_cast<double>(model.solver().mesh().elementCount()) / step_wall;
  summary["peak_rss_gb"] = rss_gb;  // the largest rank's
  {
    summary["cpu_s"] = cpu_s;  // all ranks
    summary["element_updates_per_cpu_s"] = static_cast<double>(model.solver().stepCount()) *
                                           static_cast<double>(model.solver().mesh().elementCount()) / cpu_s;
  }
  summary["receiver_peaks"] = peaks;
  summary["load_rate_hz"] = rate;
  summary["outputs"] = {dir + "/receivers.csv", dir + "/surface_vz.snap", dir + "/summary.json"};
  if (!sections.empty()) summary["outputs"].push_back(dir + "/section_vz.snap");
  // The implicit inclusions' system is factorised at the first step: its figures exist only now.
  summary["implicit_solve"] = model.summary()["implicit_solve"];
  for (size_t i = 0; i < model.solver().rigidBodyCount(); ++i) {
    const RigidBodyState& b = model.solver().rigidBody(i);
    summary["rigid_bodies"][i]["final_displacement"] =
        std::vector<double>(b.displacement.data(), b.displacement.data() + 6);
  }
  {
    io::AtomicFile f(dir + "/summary.json");
    f.stream() << summary.dump(2) << "\n";
    f.commit();
  }
  printJson(summary);
  return 0;
}

Registrar reg_soil("soil", "offline 3D soil run (loads CSV -> receiver velocities CSV + surface snapshots)", soilRun);
Registrar reg_bench("soil-bench", "soil verification and benchmarks: " + benchCaseList(), soilBench);

}  // namespace
}  // namespace railvib::tool
