// railvib_tool building-*: modal analysis, transfer functions and soil-driven response of the house.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <filesystem>

#include "command_registry.hpp"
#include "railvib/building/export.hpp"
#include "railvib/building/modal.hpp"
#include "railvib/building/model.hpp"
#include "railvib/building/response.hpp"
#include "railvib/common/site.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/io/csv.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using namespace railvib::building;
using nlohmann::json;

json modeJson(const Mode& m, size_t index, double free_mass) {
  return {{"index", index},
          {"frequency_hz", m.frequency_hz},
          {"effective_mass_kg",
           {{"x", m.effective_mass_kg.x()}, {"y", m.effective_mass_kg.y()}, {"z", m.effective_mass_kg.z()}}},
          {"effective_mass_fraction",
           {{"x", m.effective_mass_kg.x() / free_mass},
            {"y", m.effective_mass_kg.y() / free_mass},
            {"z", m.effective_mass_kg.z() / free_mass}}},
          {"torsion_fraction", m.torsion_mass_fraction},
          {"label", m.label},
          {"bending_slab", m.bending_slab},
          {"symmetric", m.symmetric},
          {"symmetry_x", m.symmetry_x},
          {"symmetry_y", m.symmetry_y}};
}

int runModes(const std::vector<std::string>& args) {
  ArgParser parser("building-modes", "fixed-base modal analysis of the house (JSON list of modes)");
  addConfigOptions(parser);
  parser.option("fmax", "highest frequency (Hz)", "50");
  parser.option("vtk", "directory for building_modes.vtk (mesh + mode shapes)");
  parser.option("vtk-frame", "frame of the VTK points: track (the site, beside the soil exports) or building", "track");
  parser.option("inp", "write an Abaqus/CalculiX .inp file of the model (fixed base, *FREQUENCY step)");
  parser.option("ccx-dat", "CalculiX .dat result of the --inp model: its frequencies are compared with ours");
  parser.flag("refine", "also run a mesh refinement study (element size x2, x1, x1/2)");
  parser.flag("free", "free-free model (rigid-body check) instead of the fixed base");
  if (!parser.parse(args)) return 0;
  const Config config = loadConfig(parser);
  const BuildingParams params = loadBuildingParams(config.root());
  const auto t0 = std::chrono::steady_clock::now();
  const BuildingModel model(params);
  ModalOptions opt;
  opt.fmax_hz = parser.getDouble("fmax", 1e-3, 1e4);
  opt.fixed_base = !parser.isSet("free");
  const ModalResult res = modalAnalysis(model, opt);
  const double hand = handComputedMass(params);

  json out;
  out["command"] = "building-modes";
  out["config"] = config.file();
  out["boundary"] = opt.fixed_base ? "fixed foundation" : "free-free";
  out["mesh"] = {{"element_size_m", params.element_size_m},
                 {"nodes", model.mesh().nodes.size()},
                 {"elements", model.mesh().elements.size()},
                 {"free_dofs", res.dof_count}};
  out["mass"] = {{"model_kg", model.totalMass()},
                 {"hand_computed_kg", hand},
                 {"relative_difference", model.totalMass() / hand - 1.0},
                 {"free_part_kg", res.free_mass_kg}};
  json modes = json::array();
  for (size_t i = 0; i < res.modes.size(); ++i) modes.push_back(modeJson(res.modes[i], i + 1, res.free_mass_kg));
  out["modes"] = modes;
  out["cumulative_effective_mass_fraction"] = {{"x", res.cumulative_effective_mass_fraction.x()},
                                               {"y", res.cumulative_effective_mass_fraction.y()},
                                               {"z", res.cumulative_effective_mass_fraction.z()}};
  out["paper_hz"] = {{"first_floor_bending_symmetric", 15.0},
                     {"other_bending", {23.8, 25.5, 27.0}},
                     {"wall_flexure_range", {25.0, 30.0}}};
  out["modal_seconds"] = res.seconds;

  if (parser.has("vtk")) {
    std::filesystem::create_directories(parser.get("vtk"));
    const std::string path = (std::filesystem::path(parser.get("vtk")) / "building_modes.vtk").string();
    ExportFrame frame;
    frame.frame_name = parser.get("vtk-frame");
    if (frame.frame_name == "track") {
      const BuildingPlacement placement = loadBuildingPlacement(config.root());
      frame.offset_m = Eigen::Vector3d(placement.origin_x_m, placement.origin_y_m, 0.0);
    } else if (frame.frame_name != "building") {
      throw ArgError("building-modes: --vtk-frame must be track or building, not '" + frame.frame_name + "'");
    }
    writeVtk(model, res.modes, path, frame);
    out["vtk"] = path;
    out["vtk_frame"] = frame.frame_name;
    out["vtk_offset_m"] = {frame.offset_m.x(), frame.offset_m.y(), frame.offset_m.z()};
  }
  if (parser.has("inp")) {
    writeInp(model, static_cast<int>(std::min<size_t>(res.modes.size(), 30)), parser.get("inp"));
    out["inp"] = parser.get("inp");
  }
  if (parser.has("ccx-dat")) {
    const std::vector<double> fc = readCalculixFrequencies(parser.get("ccx-dat"));
    json cmp = json::array();
    for (size_t i = 0; i < std::min(fc.size(), res.modes.size()); ++i)
      cmp.push_back({{"index", i + 1},
                     {"railvib_hz", res.modes[i].frequency_hz},
                     {"calculix_hz", fc[i]},
                     {"relative_difference", res.modes[i].frequency_hz / fc[i] - 1.0}});
    out["calculix_comparison"] = cmp;
  }
  if (parser.isSet("refine")) {
    json study = json::array();
    for (double factor : {2.0, 1.0, 0.5}) {
      BuildingParams p = params;
      p.element_size_m = params.element_size_m * factor;
      const BuildingModel m(p);
      ModalOptions o = opt;
      o.min_modes = 8;
      o.fmax_hz = 0.0;  // just the lowest modes
      const ModalResult r = modalAnalysis(m, o);
      json f = json::array();
      for (size_t i = 0; i < 8 && i < r.modes.size(); ++i) f.push_back(r.modes[i].frequency_hz);
      study.push_back({{"element_size_m", p.element_size_m},
                       {"free_dofs", r.dof_count},
                       {"frequencies_hz", f},
                       {"seconds", r.seconds}});
    }
    out["refinement"] = study;
  }
  out["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  printJson(out);
  return 0;
}

int runTf(const std::vector<std::string>& args) {
  ArgParser parser(
      "building-tf",
      "transfer functions: uniform vertical foundation velocity -> vertical velocity at the response points");
  addConfigOptions(parser);
  parser.option("csv", "output CSV (frequency_hz, <point>_abs, <point>_phase_rad ...)");
  parser.option("duration", "simulated time after the impulse (s)", "6.0");
  parser.option("dt", "sample period (s)", "1e-3");
  parser.option("fmax", "highest frequency of the transfer functions (Hz)", "60");
  parser.option("df", "frequency step of the DFT (Hz)", "0.05");
  if (!parser.parse(args)) return 0;
  if (!parser.has("csv")) throw ArgError("building-tf: --csv is required");
  const Config config = loadConfig(parser);
  const BuildingParams params = loadBuildingParams(config.root());
  const auto t0 = std::chrono::steady_clock::now();
  const BuildingModel model(params);
  TransferFunctionOptions opt;
  opt.duration_s = parser.getDouble("duration", 1e-3, 3600.0);
  opt.sample_period_s = parser.getDouble("dt", 1e-7, 1.0);
  opt.fmax_hz = parser.getDouble("fmax", 1e-3, 1e4);
  opt.df_hz = parser.getDouble("df", 1e-3, 1e3);
  const TransferFunctions tf = impulseTransferFunctions(model, opt);
  ModalOptions mo;
  mo.fmax_hz = opt.fmax_hz;
  const ModalResult modes = modalAnalysis(model, mo);

  std::vector<std::string> cols{"frequency_hz"};
  for (const auto& n : tf.names) {
    cols.push_back(n + "_abs");
    cols.push_back(n + "_phase_rad");
  }
  io::CsvWriter csv(parser.get("csv"), cols);
  for (size_t j = 0; j < tf.frequency_hz.size(); ++j) {
    std::vector<double> row{tf.frequency_hz[j]};
    for (int p = 0; p < tf.tf.cols(); ++p) {
      row.push_back(std::abs(tf.tf(j, p)));
      row.push_back(std::arg(tf.tf(j, p)));
    }
    csv.row(row);
  }
  csv.commit();

  json out;
  out["command"] = "building-tf";
  out["csv"] = parser.get("csv");
  json points = json::array();
  for (int p = 0; p < tf.tf.cols(); ++p) {
    json peaks = json::array();
    for (size_t j = 1; j + 1 < tf.frequency_hz.size(); ++j) {
      const double a = std::abs(tf.tf(j, p));
      // a resonance: above 2 and the largest value within +-1 Hz
      bool is_peak = a > 2.0;
      for (size_t k = 0; k < tf.frequency_hz.size() && is_peak; ++k)
        if (k != j && std::abs(tf.frequency_hz[k] - tf.frequency_hz[j]) <= 1.0 && std::abs(tf.tf(k, p)) > a)
          is_peak = false;
      if (is_peak) {
        double nearest = 0.0;
        for (const Mode& m : modes.modes)
          if (std::abs(m.frequency_hz - tf.frequency_hz[j]) < std::abs(nearest - tf.frequency_hz[j]))
            nearest = m.frequency_hz;
        peaks.push_back({{"frequency_hz", tf.frequency_hz[j]}, {"abs", a}, {"nearest_mode_hz", nearest}});
      }
    }
    double low = 0.0;
    for (size_t j = 0; j < tf.frequency_hz.size(); ++j)
      if (tf.frequency_hz[j] > 0.0 && tf.frequency_hz[j] <= 2.0)
        low = std::max(low, std::abs(std::abs(tf.tf(j, p)) - 1.0));
    const ResponseNode& rn = model.responseNodes()[p];
    points.push_back({{"name", tf.names[p]},
                      {"node_position_m", {rn.position.x(), rn.position.y(), rn.position.z()}},
                      {"max_deviation_from_1_below_2hz", low},
                      {"peaks", peaks}});
  }
  out["points"] = points;
  json mf = json::array();
  for (const Mode& m : modes.modes) mf.push_back(m.frequency_hz);
  out["modal_frequencies_hz"] = mf;
  out["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  printJson(out);
  return 0;
}

int runResponse(const std::vector<std::string>& args) {
  ArgParser parser("building-response", "velocities at the response points driven by soil footprint velocities");
  addConfigOptions(parser);
  parser.option("footprint",
                "CSV: time_s, then <footprint point>_vx, _vy, _vz for every point of building-footprint (m/s)");
  parser.option("out", "output CSV: time_s, <point>_vx, _vy, _vz (m/s)");
  parser.option("block", "samples per block fed to the streaming solver", "256");
  if (!parser.parse(args)) return 0;
  if (!parser.has("footprint") || !parser.has("out"))
    throw ArgError("building-response: --footprint and --out are required");
  const Config config = loadConfig(parser);
  const BuildingParams params = loadBuildingParams(config.root());
  const auto t0 = std::chrono::steady_clock::now();
  const BuildingModel model(params);
  const io::CsvTable in = io::readCsv(parser.get("footprint"));
  if (in.rows.size() < 2) throw std::runtime_error(in.path + ": need at least two samples");
  const size_t tcol = in.column("time_s");
  const double dt = io::uniformStep(in, tcol);
  BuildingResponseSolver solver(model, dt);
  std::vector<size_t> cols;
  for (const FootprintPoint& f : solver.footprint())
    for (const char* c : {"_vx", "_vy", "_vz"}) cols.push_back(in.column(f.name + c));
  const double bound = loadStreamLimits(config.root()).velocity_m_s;
  for (size_t i = 0; i < in.rows.size(); ++i) {
    for (size_t c : cols) {
      if (!(std::abs(in.rows[i][c]) <= bound)) {
        throw std::runtime_error(in.where(i) + ": column '" + in.columns[c] + "' = " + formatValue(in.rows[i][c]) +
                                 " m/s: beyond the " + formatValue(bound) +
                                 " m/s a velocity may be (limits.velocity_m_s)");
      }
    }
  }
  std::vector<std::string> out_cols{"time_s"};
  for (const auto& n : solver.outputColumnNames()) out_cols.push_back(n);
  io::CsvWriter csv(parser.get("out"), out_cols);
  const size_t block = static_cast<size_t>(std::max(1L, parser.getInt("block", 1, 10000000)));
  Eigen::VectorXd peak = Eigen::VectorXd::Zero(3 * solver.responsePoints().size());
  for (size_t start = 0; start < in.rows.size(); start += block) {
    const size_t n = std::min(block, in.rows.size() - start);
    Eigen::MatrixXd v(n, cols.size());
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < cols.size(); ++c) v(i, c) = in.rows[start + i][cols[c]];
    const Eigen::MatrixXd o = solver.process(start, v);
    for (size_t i = 0; i < n; ++i) {
      std::vector<double> row{in.rows[start + i][tcol]};
      for (int c = 0; c < o.cols(); ++c) {
        row.push_back(o(i, c));
        peak[c] = std::max(peak[c], std::abs(o(i, c)));
      }
      csv.row(row);
    }
  }
  csv.commit();
  json out;
  out["command"] = "building-response";
  out["out"] = parser.get("out");
  out["samples"] = in.rows.size();
  out["sample_period_s"] = dt;
  out["substeps"] = solver.substeps();
  json pts = json::array();
  for (size_t p = 0; p < solver.responsePoints().size(); ++p)
    pts.push_back({{"name", solver.responsePoints()[p].name},
                   {"peak_velocity_m_s", {peak[3 * p], peak[3 * p + 1], peak[3 * p + 2]}}});
  out["points"] = pts;
  out["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  printJson(out);
  return 0;
}

int runFootprint(const std::vector<std::string>& args) {
  ArgParser parser("building-footprint", "footprint points (track frame) where the soil must output velocities");
  addConfigOptions(parser);
  if (!parser.parse(args)) return 0;
  const Config config = loadConfig(parser);
  const BuildingParams params = loadBuildingParams(config.root());
  json pts = json::array();
  for (const FootprintPoint& f : footprintPoints(params))
    pts.push_back({{"name", f.name}, {"x_m", f.x_track_m}, {"y_m", f.y_track_m}, {"z_m", f.z_track_m}});
  printJson({{"command", "building-footprint"}, {"frame", "track"}, {"points", pts}});
  return 0;
}

const Registrar kModes("building-modes", "fixed-base modal analysis of the house", runModes);
const Registrar kTf("building-tf", "impulse transfer functions foundation -> floors", runTf);
const Registrar kResponse("building-response", "house response to soil footprint velocities", runResponse);
const Registrar kFootprint("building-footprint", "footprint receiver points for the soil model", runFootprint);

}  // namespace
}  // namespace railvib::tool
