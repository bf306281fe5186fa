// The house on a very stiff soil: two-way against one-way (stiff_soil_check.hpp).
#include "railvib/coupling/stiff_soil_check.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include "railvib/building/model.hpp"
#include "railvib/building/params.hpp"
#include "railvib/building/response.hpp"
#include "railvib/common/config.hpp"
#include "railvib/common/site.hpp"
#include "railvib/coupling/house_foundation.hpp"
#include "railvib/soil/soil_model.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/soil/ssi_verification.hpp"

namespace railvib::coupling {
namespace {

std::string num(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("stiff-soil check: " + what);
}

// The soil run's receiver frames, receiver by receiver (frames x 3, m/s).
struct SoilRun {
  std::map<std::string, Eigen::MatrixXd> velocity;
  double seconds = 0.0, dt_s = 0.0, hx_m = 0.0;
  size_t elements = 0;
  uint64_t steps = 0;
  double rate_hz = 0.0;
  double carried_soil_mass_kg = 0.0;
};

SoilRun runSoil(const Config& cfg, const StiffSoilSpec& spec, bool two_way) {
  const auto t0 = std::chrono::steady_clock::now();
  const ConfigNode root = cfg.root();
  soil::SoilParams params = soil::loadSoilParams(root, houseReceivers(root, true));
  const std::vector<double> sleepers = params.track.sleeperPositions();
  require(!sleepers.empty(), "the scenario has no sleepers");
  const std::vector<soil::RigidBodySpec> bodies = attachHouse(root, params);
  require(bodies.size() == (two_way ? 1u : 0u), "building.coupling did not give the expected foundation body");
  // Loads at 10 samples per pulse millisecond or more: the soil interpolates them to its step.
  const double load_rate_hz = std::max(2000.0, 20.0 / spec.pulse_s);
  soil::SoilModel model(params, sleepers, load_rate_hz, bodies);
  size_t loaded = 0;
  for (size_t s = 1; s < sleepers.size(); ++s) {
    if (std::abs(sleepers[s]) < std::abs(sleepers[loaded])) loaded = s;
  }
  const size_t frames = static_cast<size_t>(std::ceil(spec.duration_s * load_rate_hz)) + 1;
  std::vector<double> loads(frames * sleepers.size(), 0.0);
  for (size_t f = 0; f < frames; ++f) {
    loads[f * sleepers.size() + loaded] =
        spec.force_n * soil::hannPulse(static_cast<double>(f) / load_rate_hz, spec.pulse_s);
  }
  model.pushLoads(0, loads.data(), frames);
  model.finishLoads();

  SoilRun run;
  std::vector<std::vector<double>> rows(model.receivers().size());
  soil::ReceiverBlock block;
  auto drain = [&] {
    model.takeReceiverSamples(block);
    run.rate_hz = block.rate_hz;
    for (size_t r = 0; r < block.names.size(); ++r) {
      for (size_t f = 0; f < block.frames(); ++f) {
        for (size_t c = 0; c < 3; ++c) rows[r].push_back(block.velocity_m_s[(f * block.names.size() + r) * 3 + c]);
      }
    }
  };
  run.steps = model.finishRun(static_cast<double>(frames - 1) / load_rate_hz, 0.05, [&] {
    drain();
    return true;
  });
  drain();
  for (size_t r = 0; r < model.receivers().size(); ++r) {
    const Eigen::Index n = static_cast<Eigen::Index>(rows[r].size() / 3);
    run.velocity[model.receivers()[r].name] =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(rows[r].data(), n, 3);
  }
  run.dt_s = model.dt();
  run.hx_m = model.solver().mesh().hx;
  run.elements = model.solver().mesh().elementCount();
  if (two_way) run.carried_soil_mass_kg = model.solver().rigidBody(0).carried_soil_mass_kg;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

// The footprint receivers' velocities, 3 columns per footprint point (footprintPoints order).
Eigen::MatrixXd footprintInput(const SoilRun& run, const std::vector<building::FootprintPoint>& footprint) {
  Eigen::Index frames = -1;
  for (const auto& f : footprint) {
    const auto it = run.velocity.find(f.name);
    require(it != run.velocity.end(), "footprint point '" + f.name + "' is not a soil receiver");
    frames = frames < 0 ? it->second.rows() : std::min(frames, it->second.rows());
  }
  Eigen::MatrixXd in(frames, 3 * static_cast<Eigen::Index>(footprint.size()));
  for (size_t k = 0; k < footprint.size(); ++k) {
    in.middleCols<3>(3 * static_cast<Eigen::Index>(k)) = run.velocity.at(footprint[k].name).topRows(frames);
  }
  return in;
}

double rms(const Eigen::VectorXd& v) {
  return v.size() ? std::sqrt(v.squaredNorm() / static_cast<double>(v.size())) : 0.0;
}

}  // namespace

StiffSoilResult runStiffSoilCheck(const StiffSoilSpec& spec) {
  require(spec.shear_wave_speed_m_s > 0.0 && std::isfinite(spec.shear_wave_speed_m_s), "shear wave speed must be > 0");
  require(spec.density_kg_m3 > 0.0 && spec.poisson_ratio > -1.0 && spec.poisson_ratio < 0.5,
          "density must be > 0 and the Poisson ratio in (-1, 0.5)");
  require(spec.element_size_m > 0.0 && spec.level_m > 0.0 && spec.margin_m > 0.0 && spec.depth_m > 0.0,
          "element size, level, margin and depth must be > 0");
  require(spec.pulse_s > 0.0 && spec.duration_s > spec.pulse_s, "the run must be longer than the pulse");
  const Config scenario = Config::load(spec.scenario_file, spec.overrides);
  const building::BuildingParams house = building::loadBuildingParams(scenario.root());
  const soil::SoilParams scenario_soil = soil::loadSoilParams(scenario.root());
  const double f_max = scenario_soil.mesh.f_max_hz;

  // Plan grid with the foundation's edges on node lines.
  const double h = house.width_m / std::ceil(house.width_m / spec.element_size_m - 1e-9);
  const double along = house.length_m / h;
  require(std::abs(along - std::round(along)) < 1e-6, "element size " + num(h) + " m divides the width " +
                                                          num(house.width_m) + " m but not the length " +
                                                          num(house.length_m) + " m: choose one that divides both");
  const double epw = spec.shear_wave_speed_m_s / (f_max * spec.level_m);
  require(epw >= 4.0 && epw <= 100.0,
          "Vs / (f_max level) = " + num(epw) + " elements per wavelength, outside 4-100: change level_m or the speed");
  require(spec.level_m > house.foundation_depth_m, "level_m must exceed the foundation depth");
  const double margin = h * std::ceil(spec.margin_m / h - 1e-9);
  const double origin_y = loadSiteLayout(scenario.root()).exterior_rail_y_m + spec.front_wall_distance_m;
  const double front_cells = std::ceil((origin_y + margin) / h - 1e-9);
  const double y_min = origin_y - h * front_cells, y_max = origin_y + house.width_m + margin;
  const double x_half = 0.5 * house.length_m + margin;

  // Rock: a layer down to the foundation's base (a node plane there), one to the first level, the half-space.
  const double g = spec.density_kg_m3 * spec.shear_wave_speed_m_s * spec.shear_wave_speed_m_s;
  const std::string mat = "young_modulus_pa: " + num(2.0 * g * (1.0 + spec.poisson_ratio)) +
                          ", density_kg_m3: " + num(spec.density_kg_m3) + ", poisson_ratio: " + num(spec.poisson_ratio);
  std::vector<std::string> overrides = spec.overrides;
  overrides.insert(overrides.end(),
                   {
                       "soil.layers=[{thickness_m: " + num(house.foundation_depth_m) + ", " + mat +
                           "}, {thickness_m: " + num(spec.level_m - house.foundation_depth_m) + ", " + mat + "}]",
                       "soil.half_space={" + mat + "}",
                       "soil.rayleigh_beta_s=" + num(spec.rayleigh_beta_s),
                       "soil.mesh.elements_per_wavelength=" + num(epw),
                       "soil.mesh.max_plane_size_m=" + num(h),
                       "soil.mesh.x_min_m=" + num(-x_half),
                       "soil.mesh.x_max_m=" + num(x_half),
                       "soil.mesh.y_min_m=" + num(y_min),
                       "soil.mesh.y_max_m=" + num(y_max),
                       "soil.mesh.depth_m=" + num(spec.depth_m),
                       "soil.mesh.threads=" + std::to_string(spec.threads),
                       "soil.mesh.ranks=0",
                       "soil.boundary.method=dashpots",
                       // The premise: the house on a rigid base (the scenario's box may be meshed, which
                       // the check's coarse plan grid cannot hold).
                       "building.foundation.model=rigid",
                       "site.building.front_wall_distance_from_rail_m=" + num(spec.front_wall_distance_m),
                       "site.building.center_x_m=0.0",
                   });
  overrides.push_back("building.coupling=one_way");
  const Config one_way = Config::load(spec.scenario_file, overrides);
  overrides.back() = "building.coupling=two_way";
  const Config two_way = Config::load(spec.scenario_file, overrides);

  StiffSoilResult out;
  out.shear_wave_speed_m_s = spec.shear_wave_speed_m_s;
  const SoilRun ff = runSoil(one_way, spec, false);
  const SoilRun tw = runSoil(two_way, spec, true);
  out.hx_m = tw.hx_m;
  out.dt_s = tw.dt_s;
  out.elements = tw.elements;
  out.steps = tw.steps;
  out.seconds_free_field = ff.seconds;
  out.seconds_two_way = tw.seconds;

  const building::BuildingParams bp_one = building::loadBuildingParams(one_way.root());
  const building::BuildingParams bp_two = building::loadBuildingParams(two_way.root());
  const building::BuildingModel model_one(bp_one), model_two(bp_two);
  out.house_mass_kg = model_two.totalMass();
  out.carried_soil_mass_kg = tw.carried_soil_mass_kg;
  const std::vector<building::FootprintPoint> footprint = building::footprintPoints(bp_two);
  const Eigen::MatrixXd in_ff = footprintInput(ff, footprint), in_tw = footprintInput(tw, footprint);
  const Eigen::Index frames = std::min(in_ff.rows(), in_tw.rows());
  const double period = 1.0 / ff.rate_hz;

  // The rigid base motion of each input (6 DOFs about the plan centre), and what of the free field it misses.
  const Eigen::MatrixXd fit = building::footprintRigidFit(bp_two);
  const Eigen::MatrixXd rigid_map = fit.completeOrthogonalDecomposition().pseudoInverse();  // the 3n x 6 map
  const Eigen::MatrixXd q_ff = in_ff.topRows(frames) * fit.transpose(), q_tw = in_tw.topRows(frames) * fit.transpose();
  out.foundation_vz_vs_free_field_fit = rms(q_tw.col(2) - q_ff.col(2)) / rms(q_ff.col(2));
  const Eigen::MatrixXd residual = in_ff.topRows(frames) - q_ff * rigid_map.transpose();
  double res2 = 0.0, all2 = 0.0;
  for (Eigen::Index c = 2; c < in_ff.cols(); c += 3) {
    res2 += residual.col(c).squaredNorm();
    all2 += in_ff.col(c).topRows(frames).squaredNorm();
  }
  out.free_field_non_rigid_share = std::sqrt(res2 / all2);

  building::BuildingResponseSolver pointwise(model_one, period), rigid(model_two, period);
  const Eigen::MatrixXd r_pointwise = pointwise.process(0, in_ff.topRows(frames));
  const Eigen::MatrixXd r_fit = rigid.process(0, in_ff.topRows(frames));
  rigid.reset();
  const Eigen::MatrixXd r_two = rigid.process(0, in_tw.topRows(frames));
  const auto& points = rigid.responsePoints();
  for (size_t p = 0; p < points.size(); ++p) {
    StiffSoilPoint sp;
    sp.name = points[p].name;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index col = 3 * static_cast<Eigen::Index>(p) + c;
      StiffSoilComponent& k = sp.component[c];
      k.rms_two_way_m_s = rms(r_two.col(col));
      k.rms_rigid_fit_m_s = rms(r_fit.col(col));
      k.vs_rigid_fit = rms(r_two.col(col) - r_fit.col(col)) / rms(r_fit.col(col));
      k.vs_one_way = rms(r_two.col(col) - r_pointwise.col(col)) / rms(r_pointwise.col(col));
    }
    out.points.push_back(sp);
  }
  return out;
}

}  // namespace railvib::coupling
