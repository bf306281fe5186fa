// railvib_tool ssi-bench footing-static | footing-impedance | block | kinematic | stiff-soil: verification of the
// soil-structure interaction model against published solutions (docs/soil.md, "Soil-structure
// interaction: verification"). The computations are in railvib/soil/ssi_verification.hpp.
#include <cmath>
#include <sstream>
#include <vector>

#include "command_registry.hpp"
#include "railvib/coupling/stiff_soil_check.hpp"
#include "railvib/io/csv.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/ssi_verification.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using nlohmann::json;
using namespace railvib::soil;

std::vector<double> numberList(const ArgParser& p, const std::string& key) {
  // Element sizes and boxes (m), dimensionless frequencies, mass ratios, wave speeds (m/s): all positive.
  return p.getDoubles(key, 1e-9, 1e6);
}

// An option whose default is its case's spec default (one place for it): assigned only when given.
void assignIfGiven(const ArgParser& p, const std::string& key, double& value, double lo, double hi) {
  if (p.has(key) && !p.get(key).empty()) value = p.getDouble(key, lo, hi);
}

json materialJson(const Material& m) {
  return {{"shear_modulus_pa", m.shearModulus()},
          {"density_kg_m3", m.density_kg_m3},
          {"poisson_ratio", m.poisson_ratio},
          {"vs_m_s", m.vs()},
          {"vp_m_s", m.vp()}};
}

FootingModelSpec footingSpec(const ArgParser& p, double h_m) {
  FootingModelSpec f;
  f.material.poisson_ratio = p.getDouble("nu", 0.0, 0.4999);
  // Keep Vs = 100 m/s and rho = 2000 kg/m3 whatever nu.
  f.material.young_modulus_pa = 2.0 * (1.0 + f.material.poisson_ratio) * 2000.0 * 100.0 * 100.0;
  f.half_width_m = 1.0;
  f.h_m = h_m;
  f.precision = p.get("precision") == "float" ? Precision::Float : Precision::Double;
  f.threads = static_cast<int>(p.getInt("threads", 0, 1024));
  if (p.has("embedment")) {
    f.embedment_m = p.getDouble("embedment", 0.0, 100.0);
    const std::string foundation = p.get("foundation");
    if (foundation != "rigid" && foundation != "meshed") {
      throw ArgError("ssi-bench: --foundation must be rigid or meshed");
    }
    f.meshed = foundation == "meshed";
    f.wall_m = p.getDouble("wall", 0.0, 100.0);
    if (f.meshed && !(f.embedment_m > 0.0)) throw ArgError("ssi-bench: --foundation meshed needs --embedment > 0");
  }
  return f;
}

// Mesh sweep in the smallest box and box sweep with the coarsest mesh, combined as
// K_inf = K_{h->0}(R0) K_{R->inf}(h0) / K(h0, R0): the two errors (edge singularity, far boundary) are
// nearly independent (checked in docs/soil.md).
json footingStatic(const ArgParser& p) {
  json out;
  std::vector<FootingMode> modes;
  const std::string mode = p.get("mode");
  if (mode == "vertical" || mode == "both") modes.push_back(FootingMode::Vertical);
  if (mode == "rocking" || mode == "both") modes.push_back(FootingMode::Rocking);
  if (modes.empty()) throw ArgError("ssi-bench: --mode must be vertical, rocking or both");
  const std::vector<double> hs = numberList(p, "h"), boxes = numberList(p, "boxes");
  if (hs.size() < 2) throw ArgError("ssi-bench: footing-static needs two element sizes or more (--h)");
  const double tol = p.getDouble("tolerance", 1e-12, 1.0);
  for (FootingMode fm : modes) {
    const bool vertical = fm == FootingMode::Vertical;
    json jm;
    // Box sweep with the coarsest mesh.
    const FootingModelSpec coarse = footingSpec(p, hs.front());
    const StaticStiffnessResult box_sweep = runFootingStatic(coarse, fm, boxes, tol);
    const double unit = box_sweep.unit;
    json runs = json::array();
    for (const StaticStiffnessRun& run : box_sweep.runs) {
      runs.push_back({{"box_m", run.box_m},
                      {"normalised", run.stiffness / unit},
                      {"residual", run.residual},
                      {"steps", run.steps},
                      {"elements", run.elements},
                      {"seconds", run.seconds}});
    }
    jm["box_sweep"] = {{"h_m", hs.front()},
                       {"runs", runs},
                       {"fitted_exponent_p", box_sweep.exponent},
                       {"extrapolated_normalised", box_sweep.extrapolated / unit},
                       {"extrapolated_p1_normalised", box_sweep.extrapolated_inverse_r / unit}};
    // Mesh sweep in the smallest box (its coarsest run is the box sweep's first).
    std::vector<StaticStiffnessRun> mesh_runs{box_sweep.runs.front()};
    for (size_t i = 1; i < hs.size(); ++i)
      mesh_runs.push_back(runFootingStaticBox(footingSpec(p, hs[i]), fm, boxes.front(), tol));
    json mruns = json::array();
    for (size_t i = 0; i < hs.size(); ++i) {
      mruns.push_back({{"h_m", hs[i]},
                       {"elements_across_half_width", 1.0 / hs[i]},
                       {"normalised", mesh_runs[i].stiffness / unit},
                       {"residual", mesh_runs[i].residual},
                       {"steps", mesh_runs[i].steps},
                       {"elements", mesh_runs[i].elements},
                       {"seconds", mesh_runs[i].seconds}});
    }
    const size_t n = hs.size();
    const double k_h0 =
        extrapolateToZeroSize(hs[n - 2], mesh_runs[n - 2].stiffness, hs[n - 1], mesh_runs[n - 1].stiffness);
    json jmesh = {{"box_m", mesh_runs.front().box_m}, {"runs", mruns}, {"extrapolated_normalised", k_h0 / unit}};
    if (n >= 3) {
      jmesh["previous_pair_extrapolated_normalised"] =
          extrapolateToZeroSize(hs[n - 3], mesh_runs[n - 3].stiffness, hs[n - 2], mesh_runs[n - 2].stiffness) / unit;
      jmesh["fitted_order_q"] = convergenceOrder(hs[n - 3], mesh_runs[n - 3].stiffness, hs[n - 2],
                                                 mesh_runs[n - 2].stiffness, hs[n - 1], mesh_runs[n - 1].stiffness);
    }
    jm["mesh_sweep"] = jmesh;
    const double box_factor = box_sweep.extrapolated / box_sweep.runs.front().stiffness;
    const double fe = k_h0 * box_factor;
    jm["box_factor"] = box_factor;
    jm["fe_normalised"] = fe / unit;
    const Material& m = coarse.material;
    const double b = coarse.half_width_m;
    const double d = coarse.embedment_m;
    if (d > 0.0 && !vertical) throw ArgError("ssi-bench: an embedded footing is checked in the vertical mode only");
    const double gazetas = !vertical ? gazetasRockingStiffnessX(m, b, b)
                           : d > 0.0 ? gazetasEmbeddedVerticalStiffness(m, b, b, d)
                                     : gazetasVerticalStiffness(m, b, b);
    const double pais = !vertical ? paisKauselRockingStiffnessX(m, b, b)
                        : d > 0.0 ? paisKauselEmbeddedVerticalStiffness(m, b, b, d)
                                  : paisKauselVerticalStiffness(m, b, b);
    jm["unit"] = vertical ? "G B / (1 - nu)" : "G B^3 / (1 - nu)";
    jm["gazetas_1991_normalised"] = gazetas / unit;
    if (d > 0.0) {
      jm["embedment_m"] = d;
      jm["foundation"] = coarse.meshed ? "meshed concrete box" : "rigid";
      jm["gazetas_1991_surface_normalised"] = gazetasVerticalStiffness(m, b, b) / unit;
    }
    jm["pais_kausel_1988_normalised"] = pais / unit;
    jm["error_vs_gazetas"] = fe / gazetas - 1.0;
    jm["error_vs_pais_kausel"] = fe / pais - 1.0;
    if (!vertical) {
      const double gy = gazetasRockingStiffnessY(m, b, b);
      jm["gazetas_1991_about_short_axis_normalised"] = gy / unit;
      jm["error_vs_gazetas_about_short_axis"] = fe / gy - 1.0;
    }
    out[vertical ? "vertical" : "rocking"] = jm;
    out["material"] = materialJson(m);
  }
  out["half_width_m"] = 1.0;
  out["method"] =
      "quarter model (symmetry x = 0; y = 0 symmetric for vertical, antisymmetric for rocking), fixed bottom, free "
      "sides, dynamic relaxation; box sweep (coarsest mesh): flexibility f(R) = f_inf + a R^-p through the three "
      "largest boxes, p fitted; mesh sweep (smallest box): linear in h through the two finest; combined as "
      "K_h->0(R0) K_R->inf(h0) / K(h0, R0)";
  return out;
}

json footingImpedance(const ArgParser& p) {
  const std::vector<double> hs = numberList(p, "h");
  std::vector<ImpedanceResult> results;
  json out, meshes = json::array();
  ImpedanceSpec spec;
  for (double h : hs) {
    spec.footing = footingSpec(p, h);
    spec.box_m = numberList(p, "boxes").back();
    if (p.has("a0") && !p.get("a0").empty()) spec.a0 = numberList(p, "a0");
    results.push_back(runFootingImpedance(spec));
    const ImpedanceResult& r = results.back();
    json pts = json::array();
    for (const ImpedancePoint& q : r.points) {
      pts.push_back({{"a0", q.a0},
                     {"stiffness_normalised", q.fe.stiffness_n_m / r.stiffness_unit},
                     {"dashpot_normalised", q.fe.dashpot_n_s_m / r.dashpot_unit}});
    }
    meshes.push_back({{"h_m", h},
                      {"points", pts},
                      {"static_stiffness_normalised", r.static_stiffness_n_m / r.stiffness_unit},
                      {"elements", r.elements},
                      {"dt_s", r.dt_s},
                      {"steps", r.steps},
                      {"end_displacement_over_peak", r.end_displacement},
                      {"seconds", r.seconds}});
    if (p.has("csv") && !p.get("csv").empty() && results.size() == 1) {
      io::CsvWriter csv(p.get("csv"), {"t_s", "displacement_m", "load_n", "soil_force_n"});
      for (size_t i = 0; i < r.t_s.size(); ++i) {
        csv.row({r.t_s[i], r.displacement_m[i], r.load_n[i], r.soil_force_n[i]});
      }
      csv.commit();
    }
  }
  // FE values: the finest mesh, or extrapolated to h = 0 from the two finest.
  const ImpedanceResult& fine = results.back();
  auto toZero = [&](double coarse, double v) {
    return results.size() >= 2 ? extrapolateToZeroSize(hs[hs.size() - 2], coarse, hs.back(), v) : v;
  };
  const ImpedanceResult& coarse = results[results.size() >= 2 ? results.size() - 2 : 0];
  const double ks_fe = toZero(coarse.static_stiffness_n_m, fine.static_stiffness_n_m);
  const Material& m = spec.footing.material;
  const double b = spec.footing.half_width_m, vs = m.vs();
  const double ks_gazetas = gazetasVerticalStiffness(m, b, b), ks_pk = paisKauselVerticalStiffness(m, b, b);
  json pts = json::array();
  for (size_t i = 0; i < fine.points.size(); ++i) {
    const ImpedancePoint& q = fine.points[i];
    const VerticalImpedance fe{toZero(coarse.points[i].fe.stiffness_n_m, q.fe.stiffness_n_m),
                               toZero(coarse.points[i].fe.dashpot_n_s_m, q.fe.dashpot_n_s_m)};
    const DynamicCoefficients c_fe = dynamicCoefficients(fe, ks_fe, b, vs);
    const DynamicCoefficients c_g = dynamicCoefficients(q.gazetas, ks_gazetas, b, vs);
    const DynamicCoefficients c_pk = dynamicCoefficients(q.pais_kausel, ks_pk, b, vs);
    json row = {{"a0", q.a0},
                {"frequency_hz", q.frequency_hz},
                {"fe_stiffness_normalised", fe.stiffness_n_m / fine.stiffness_unit},
                {"fe_dashpot_normalised", fe.dashpot_n_s_m / fine.dashpot_unit},
                {"gazetas_stiffness_normalised", q.gazetas.stiffness_n_m / fine.stiffness_unit},
                {"gazetas_dashpot_normalised", q.gazetas.dashpot_n_s_m / fine.dashpot_unit},
                {"pais_kausel_stiffness_normalised", q.pais_kausel.stiffness_n_m / fine.stiffness_unit},
                {"pais_kausel_dashpot_normalised", q.pais_kausel.dashpot_n_s_m / fine.dashpot_unit},
                {"fe_k", c_fe.k},
                {"fe_c", c_fe.c},
                {"gazetas_k", c_g.k},
                {"gazetas_c", c_g.c},
                {"pais_kausel_k", c_pk.k},
                {"pais_kausel_c", c_pk.c},
                {"k_error_vs_gazetas", c_fe.k / c_g.k - 1.0},
                {"c_error_vs_gazetas", c_fe.c / c_g.c - 1.0},
                {"k_error_vs_pais_kausel", c_fe.k / c_pk.k - 1.0},
                {"c_error_vs_pais_kausel", c_fe.c / c_pk.c - 1.0},
                {"stiffness_error_vs_gazetas", fe.stiffness_n_m / q.gazetas.stiffness_n_m - 1.0},
                {"dashpot_error_vs_gazetas", fe.dashpot_n_s_m / q.gazetas.dashpot_n_s_m - 1.0},
                {"stiffness_error_vs_pais_kausel", fe.stiffness_n_m / q.pais_kausel.stiffness_n_m - 1.0},
                {"dashpot_error_vs_pais_kausel", fe.dashpot_n_s_m / q.pais_kausel.dashpot_n_s_m - 1.0}};
    if (q.a0 > 2.0) {  // beyond Gazetas' charts
      for (const char* key :
           {"gazetas_stiffness_normalised", "gazetas_dashpot_normalised", "gazetas_k", "gazetas_c",
            "k_error_vs_gazetas", "c_error_vs_gazetas", "stiffness_error_vs_gazetas", "dashpot_error_vs_gazetas"}) {
        row[key] = nullptr;
      }
    }
    pts.push_back(row);
  }
  out["static_stiffness"] = {{"fe_low_frequency_limit_normalised", ks_fe / fine.stiffness_unit},
                             {"gazetas_normalised", ks_gazetas / fine.stiffness_unit},
                             {"pais_kausel_normalised", ks_pk / fine.stiffness_unit}};
  out["points"] = pts;
  out["fe_values"] = results.size() >= 2 ? "extrapolated to h = 0 (linear) from the two finest meshes" : "finest mesh";
  out["meshes"] = meshes;
  out["units"] = {{"stiffness", "G B / (1 - nu)"},
                  {"dashpot", "rho Vs A, A = 4 B^2"},
                  {"k_c", "K = K_s (k + i a0 c), each normalised by its own static stiffness K_s"}};
  out["material"] = materialJson(spec.footing.material);
  out["box_m"] = spec.box_m;
  out["pulse_s"] = fine.pulse_s;
  out["window_s"] = fine.window_s;
  return out;
}

json block(const ArgParser& p) {
  json rows = json::array();
  BlockSpec spec;
  const std::vector<double> hs = numberList(p, "h");
  for (double bz : numberList(p, "mass-ratio")) {
    std::vector<BlockResult> rs;
    json meshes = json::array();
    for (double h : hs) {
      spec.footing = footingSpec(p, h);
      spec.box_m = numberList(p, "boxes").back();
      spec.mass_ratio = bz;
      rs.push_back(runBlock(spec));
      const BlockResult& r = rs.back();
      meshes.push_back({{"h_m", h},
                        {"damped_hz", r.damped_hz},
                        {"resonance_hz", r.resonance_hz},
                        {"damping_ratio", r.damping_ratio},
                        {"extrema_used", r.extrema_used},
                        {"elements", r.elements},
                        {"dt_s", r.dt_s},
                        {"steps", r.steps},
                        {"seconds", r.seconds}});
      if (p.has("csv") && !p.get("csv").empty()) {
        io::CsvWriter csv(p.get("csv") + "_bz" + std::to_string(bz) + "_h" + std::to_string(h) + ".csv",
                          {"t_s", "displacement_m"});
        for (size_t i = 0; i < r.t_s.size(); ++i) csv.row({r.t_s[i], r.displacement_m[i]});
        csv.commit();
      }
    }
    // FE values: extrapolated to h = 0 from the two finest meshes (the footing's O(h) stiffness error).
    const size_t n = rs.size();
    auto fe = [&](double BlockResult::*field) {
      return n >= 2 ? extrapolateToZeroSize(hs[n - 2], rs[n - 2].*field, hs[n - 1], rs[n - 1].*field)
                    : rs.back().*field;
    };
    const LysmerAnalog& l = rs.back().lysmer;
    const double fd = fe(&BlockResult::damped_hz), fr = fe(&BlockResult::resonance_hz);
    const double zeta = fe(&BlockResult::damping_ratio);
    rows.push_back({{"mass_ratio_bz", l.mass_ratio},
                    {"mass_kg", l.mass_kg},
                    {"equivalent_radius_m", rs.back().equivalent_radius_m},
                    {"lysmer_natural_hz", l.natural_hz},
                    {"lysmer_damped_hz", l.damped_hz},
                    {"lysmer_resonance_hz", l.resonance_hz},
                    {"lysmer_damping_ratio", l.damping_ratio},
                    {"fe_damped_hz", fd},
                    {"fe_resonance_hz", fr},
                    {"fe_damping_ratio", zeta},
                    {"damped_frequency_error", fd / l.damped_hz - 1.0},
                    {"resonance_frequency_error", fr / l.resonance_hz - 1.0},
                    {"damping_ratio_error", zeta / l.damping_ratio - 1.0},
                    {"meshes", meshes}});
  }
  json out;
  out["blocks"] = rows;
  out["fe_values"] = hs.size() >= 2 ? "extrapolated to h = 0 (linear) from the two finest meshes" : "single mesh";
  out["material"] = materialJson(spec.footing.material);
  out["box_m"] = spec.box_m;
  return out;
}

json kinematic(const ArgParser& p) {
  const Config cfg = loadConfig(p);
  const SoilParams sp = loadSoilParams(cfg.root());
  KinematicSpec spec;
  spec.profile = sp.profile;
  spec.f_max_hz = sp.mesh.f_max_hz;
  spec.elements_per_wavelength = sp.mesh.elements_per_wavelength;
  spec.solver = sp.solver;
  spec.x_max_m = sp.mesh.x_max_m;
  spec.y_min_m = sp.mesh.y_min_m;
  spec.y_max_m = sp.mesh.y_max_m;
  spec.depth_m = sp.mesh.depth_m;
  spec.mass_fraction = p.getDouble("mass-fraction", 0.0, 1.0);
  assignIfGiven(p, "duration", spec.duration_s, 1e-4, 60.0);
  assignIfGiven(p, "pulse", spec.pulse_s, 1e-5, 10.0);
  const KinematicResult r = runKinematic(spec);
  json bands = json::array();
  for (const KinematicBand& b : r.bands) {
    bands.push_back({{"nominal_hz", b.nominal_hz},
                     {"ratio_foundation_over_free_field", b.ratio_centre},
                     {"ratio_foundation_over_footprint_average", b.ratio_footprint},
                     {"level_free_field_db", b.level_free_field_db},
                     {"level_foundation_db", b.level_foundation_db}});
  }
  json out;
  out["bands"] = bands;
  out["foundation_snapped"] = {{"x_m", {-r.x_max_m, r.x_max_m}},
                               {"y_m", {r.y_min_m, r.y_max_m}},
                               {"depth_m", r.depth_m},
                               {"carried_soil_mass_kg_half_model", r.carried_soil_mass_kg},
                               {"body_mass_kg_half_model", r.body_mass_kg},
                               {"mass_fraction", spec.mass_fraction}};
  out["mesh"] = {
      {"hx_m", r.hx_m}, {"hy_m", r.hy_m}, {"elements_half_model", r.elements}, {"dt_s", r.dt_s}, {"steps", r.steps}};
  out["boundary"] = boundaryMethodName(spec.solver.boundary.method);
  out["load"] = {{"x_m", 0.0}, {"y_m", spec.load_y_m}, {"hann_pulse_s", spec.pulse_s}};
  out["tail_energy_fraction"] = {{"free_field", r.tail_energy_free_field}, {"foundation", r.tail_energy_foundation}};
  out["seconds"] = {{"free_field", r.seconds_free_field}, {"foundation", r.seconds_foundation}};
  if (p.has("csv") && !p.get("csv").empty()) {
    io::CsvWriter csv(p.get("csv"), {"t_s", "v_free_field_m_s", "v_foundation_m_s", "v_free_field_footprint_m_s"});
    for (size_t i = 0; i < r.t_s.size(); ++i) {
      csv.row({r.t_s[i], r.v_free_field_m_s[i], r.v_foundation_m_s[i], r.v_free_field_footprint_m_s[i]});
    }
    csv.commit();
  }
  return out;
}

json stiffSoil(const ArgParser& p) {
  // The scenario and its overrides as every command takes them; the check swaps the soil for rock.
  coupling::StiffSoilSpec base;
  base.scenario_file = p.get("config");
  base.overrides = p.getAll("set");
  assignIfGiven(p, "distance", base.front_wall_distance_m, 0.0, 1e3);
  assignIfGiven(p, "duration", base.duration_s, 1e-4, 60.0);
  assignIfGiven(p, "pulse", base.pulse_s, 1e-5, 10.0);
  assignIfGiven(p, "margin", base.margin_m, 0.0, 1e3);
  assignIfGiven(p, "depth", base.depth_m, 0.0, 1e3);
  base.threads = static_cast<int>(p.getInt("threads", 0, 1024));
  json runs = json::array();
  for (double vs : numberList(p, "vs")) {
    coupling::StiffSoilSpec spec = base;
    spec.shear_wave_speed_m_s = vs;
    const coupling::StiffSoilResult r = coupling::runStiffSoilCheck(spec);
    json points = json::array();
    for (const auto& pt : r.points) {
      json comps;
      const char* names[3] = {"vx", "vy", "vz"};
      for (int c = 0; c < 3; ++c) {
        comps[names[c]] = {{"two_way_vs_rigid_fit_of_free_field", pt.component[c].vs_rigid_fit},
                           {"two_way_vs_one_way_pointwise", pt.component[c].vs_one_way},
                           {"rms_two_way_m_s", pt.component[c].rms_two_way_m_s},
                           {"rms_rigid_fit_m_s", pt.component[c].rms_rigid_fit_m_s}};
      }
      points.push_back({{"name", pt.name}, {"components", comps}});
    }
    runs.push_back({{"vs_m_s", vs},
                    {"points", points},
                    {"foundation_vz_two_way_vs_free_field_fit", r.foundation_vz_vs_free_field_fit},
                    {"free_field_vz_non_rigid_share", r.free_field_non_rigid_share},
                    {"house_mass_kg", r.house_mass_kg},
                    {"carried_soil_mass_kg", r.carried_soil_mass_kg},
                    {"mesh", {{"h_plan_m", r.hx_m}, {"elements", r.elements}, {"dt_s", r.dt_s}, {"steps", r.steps}}},
                    {"seconds", {{"free_field", r.seconds_free_field}, {"two_way", r.seconds_two_way}}}});
  }
  json out;
  out["runs"] = runs;
  out["front_wall_distance_m"] = base.front_wall_distance_m;
  out["box"] = {{"margin_m", base.margin_m}, {"depth_m", base.depth_m}, {"boundary", "dashpots"}};
  out["load"] = {{"sleeper", "nearest x = 0"}, {"force_n", base.force_n}, {"hann_pulse_s", base.pulse_s}};
  out["note"] =
      "rms over the run of (two-way - reference) / rms(reference) per response point and component; reference "
      "rigid_fit: the house driven by the rigid motion least-squares fitted to the free field at its footprint "
      "(isolates the inertial interaction, which vanishes as the soil stiffens); one_way_pointwise: driven point by "
      "point by the free field (adds the kinematic interaction of a rigid base under a non-uniform field)";
  return out;
}

int ssiBench(const std::vector<std::string>& args) {
  ArgParser p(
      "ssi-bench",
      "soil-structure interaction verification: footing-static | footing-impedance | block | kinematic | stiff-soil");
  p.option("case", "footing-static | footing-impedance | block | kinematic | stiff-soil (or give it as first argument)",
           "");
  p.option("h",
           "element sizes (m, footing half width B = 1 m), comma-separated, decreasing: footing-static sweeps them in "
           "the first box, the dynamic cases extrapolate to h = 0 from the two finest",
           "0.25,0.125");
  p.option("boxes",
           "quarter-box half widths = depths (m), increasing: footing-static sweeps them with the first h, the "
           "dynamic cases use the last",
           "4,6,8");
  p.option("mode", "footing-static: vertical | rocking | both", "both");
  p.option("embedment", "footing-static: embedment depth D (m, a multiple of every h; vertical mode only)", "0");
  p.option("foundation",
           "footing-static with --embedment: rigid (the soil nodes down to D carried) | meshed (a closed concrete box "
           "of implicit inclusions, E 20 GPa, rho 2400, nu 0.2, its top face carried)",
           "rigid");
  p.option("wall",
           "footing-static, meshed: thickness of the box's slabs and walls (m, a multiple of every h; "
           "0 = one element)",
           "0");
  p.option("tolerance", "footing-static: relative change of the displacement that ends the relaxation", "1e-6");
  p.option("nu", "Poisson ratio of the half-space (Vs = 100 m/s, rho = 2000 kg/m3)", "0.3333333333333333");
  p.option("a0", "footing-impedance: dimensionless frequencies w B / Vs, comma-separated (default 0.25..2.5)", "");
  p.option("mass-ratio", "block: Lysmer mass ratios B_z, comma-separated", "2,5");
  p.option("mass-fraction", "kinematic: foundation mass / mass of the soil it replaces", "0.2");
  p.option("duration", "kinematic, stiff-soil: simulated time (s; default kinematic 0.8, stiff-soil 0.5)");
  p.option("pulse", "kinematic, stiff-soil: Hann load pulse duration (s; default kinematic 0.02, stiff-soil 0.03)");
  p.option("vs", "stiff-soil: shear wave speeds of the rock (m/s), comma-separated", "10000");
  p.option("distance", "stiff-soil: the house's front wall from the rail (m; default 30)");
  p.option("margin", "stiff-soil: box beyond the house and the loaded sleeper in plan (m; default 12)");
  p.option("depth", "stiff-soil: box depth (m; default 20)");
  p.option("precision", "footing cases: double | float", "double");
  p.option("threads", "OpenMP threads (0 = all)", "0");
  p.option("csv", "write the time series to this CSV (block: prefix)", "");
  addConfigOptions(p);  // kinematic: soil profile, mesh resolution, damping, boundary, box
  std::string which;
  if (!parseWithCase(p, args, which)) return 0;
  json out;
  if (which == "footing-static") {
    out = footingStatic(p);
  } else if (which == "footing-impedance") {
    out = footingImpedance(p);
  } else if (which == "block") {
    out = block(p);
  } else if (which == "kinematic") {
    out = kinematic(p);
  } else if (which == "stiff-soil") {
    out = stiffSoil(p);
  } else {
    throw ArgError("ssi-bench: unknown case '" + which +
                   "' (footing-static | footing-impedance | block | kinematic | stiff-soil)");
  }
  out["case"] = which;
  printJson(out);
  return 0;
}

}  // namespace

const Registrar kSsiBench("ssi-bench",
                          "soil-structure interaction verification (footing stiffness, impedance, Lysmer block, "
                          "kinematic interaction)",
                          ssiBench);

}  // namespace railvib::tool
