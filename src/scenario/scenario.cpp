#include "railvib/scenario/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "railvib/building/model.hpp"
#include "railvib/common/site.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/coupling/house_foundation.hpp"
#include "railvib/signal/virtual_sensor.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/unevenness.hpp"
#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::scenario {

namespace {

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

std::vector<std::string> soilSensorsOnTheFoundation(const ConfigNode& root,
                                                    const std::vector<soil::ReceiverSpec>& receivers) {
  std::vector<std::string> out;
  if (!root.has("building") || !root.has("virtual_sensors")) return out;
  const building::BuildingParams house = building::loadBuildingParams(root);
  if (house.coupling != building::SoilCoupling::TwoWay) return out;
  const BuildingPlacement& plan = house.placement;
  for (const auto& s : signal::loadVirtualSensorConfig(root).sensors) {
    if (s.source == "building") continue;
    for (const auto& r : receivers) {
      if (r.name != s.point || !plan.containsPlanPoint(r.x_m, r.y_m)) continue;
      std::ostringstream note;
      note << "sensor " << s.spec.name << " at (" << r.x_m << ", " << r.y_m
           << ") m stands on the house's foundation (plan x " << plan.origin_x_m << ".."
           << plan.origin_x_m + plan.length_m << " m, y " << plan.origin_y_m << ".." << plan.origin_y_m + plan.width_m
           << " m): with building.coupling two_way the foundation is part of the soil, so it records the "
           << (house.foundation_model == building::FoundationModel::Meshed ? "meshed foundation's motion"
                                                                           : "foundation's rigid motion")
           << ", not the free field (that is the run with coupling one_way)";
      out.push_back(note.str());
    }
  }
  return out;
}

nlohmann::json validateScenario(const Config& config) {
  const ConfigNode root = config.root();
  const vehicle::PassageParams passage = vehicle::loadPassageParams(root);
  const vehicle::VehicleParams vehicle_params = vehicle::loadVehicleParams(root);
  // Every vehicle of the library, not only the chosen one: a bad description is refused before
  // anyone selects it, and its keys are read (so they are not taken for typos).
  for (const std::string& name : vehicle::vehicleLibrary(root)) vehicle::loadVehicleParams(root, name);
  // (Whether the tram stays on the modelled track is checked by the passage as it runs: tools such
  // as track-bench shorten track.extent on purpose.)
  const track::TrackParams track = track::loadTrackParams(root);
  const vehicle::UnevennessParams unevenness = vehicle::loadUnevennessParams(root);
  const building::BuildingParams house = building::loadBuildingParams(root);
  // The soil's receivers as the soil node asks for them, the house's footprint included.
  const soil::SoilParams soil = soil::loadSoilParams(root, coupling::houseReceivers(root, true));
  // The house in the soil (two-way): what the soil node would refuse, refused here.
  if (house.coupling == building::SoilCoupling::TwoWay) coupling::checkHouseInSoil(root, house, soil);
  loadSiteLayout(root);
  const signal::VirtualSensorConfig sensors = signal::loadVirtualSensorConfig(root);
  loadStreamLimits(root);

  // The streams between the steps: each rate within what its producer and consumer can do.
  const ConfigNode track_output = root.section("track").section("output");
  const double step_rate_hz = 1.0 / passage.time_step_s;
  if (track.load_sample_rate_hz > step_rate_hz * (1.0 + 1e-12)) {
    track_output.fail("load_sample_rate_hz",
                      "above the rate of the vehicle/track steps (1 / simulation.time_step_s = " + str(step_rate_hz) +
                          " Hz): the loads are decimated from those steps");
  }
  if (track.load_sample_rate_hz < 2.0 * soil.mesh.f_max_hz) {
    track_output.fail("load_sample_rate_hz",
                      "below twice the highest frequency the soil resolves (2 x "
                      "soil.mesh.f_max_hz = " +
                          str(2.0 * soil.mesh.f_max_hz) + " Hz, Nyquist)");
  }
  const ConfigNode vs = root.section("virtual_sensors");
  if (sensors.sample_rate_hz > soil.receiver_rate_hz * (1.0 + 1e-12)) {
    vs.fail("sample_rate_hz", "above the rate of the velocities the sensors receive (soil.output.receiver_rate_hz = " +
                                  str(soil.receiver_rate_hz) + " Hz): a sensor decimates, it cannot add samples");
  }
  // Every sensor at a point its source outputs.
  std::vector<std::string> soil_points, house_points;
  for (const auto& r : soil.receivers) soil_points.push_back(r.name);
  for (const auto& p : house.response_points) house_points.push_back(p.name);
  const std::vector<ConfigNode> entries = vs.sectionList("sensors");
  nlohmann::json sensor_list = nlohmann::json::array();
  for (size_t i = 0; i < sensors.sensors.size(); ++i) {
    const signal::VirtualSensorSetup& s = sensors.sensors[i];
    const bool in_house = s.source == "building";
    if (!contains(in_house ? house_points : soil_points, s.point)) {
      entries[i].fail(
          "point", std::string("no such ") + (in_house ? "building response point (building.response_points)"
                                                       : "soil receiver (site.ground_sensors, a sensor's position, "
                                                         "soil.output.receiver_line, the house's free-field points)"));
    }
    sensor_list.push_back({{"name", s.spec.name}, {"source", s.source}, {"point", s.point}});
  }
  // A measured profile must exist and hold a valid profile: read it as the vehicle node will.
  if (unevenness.measured.enabled) {
    try {
      vehicle::Unevenness(unevenness, track.layout.x_min_m, track.layout.x_max_m);
    } catch (const ConfigError&) {
      throw;
    } catch (const std::exception& e) {
      root.section("unevenness").section("measured_profile").fail("file", e.what());
    }
  }
  config.refuseUnknownKeys();

  nlohmann::json summary;
  summary["config"] = config.file();
  summary["valid"] = true;
  summary["sections"] = {"simulation", "vehicle", "unevenness",      "track", "soil",
                         "building",   "site",    "virtual_sensors", "limits"};
  summary["track_foundation"] = track::foundationName(track.foundation);
  summary["virtual_sensors"] = sensor_list;
  summary["notes"] = soilSensorsOnTheFoundation(root, soil.receivers);
  for (const std::string& note : config.notes()) summary["notes"].push_back(note);
  summary["rates_hz"] = {{"contact_forces", step_rate_hz},
                         {"soil_loads", track.load_sample_rate_hz},
                         {"surface_velocities", soil.receiver_rate_hz},
                         {"building_response", soil.receiver_rate_hz},
                         {"sensor_samples", sensors.sample_rate_hz}};
  summary["duration_s"] = passage.duration_s;
  // The soil box as the run will mesh it (soil.mesh.extent: fixed as given, auto fitted to the site).
  summary["soil_box_m"] = {{"extent", soil.box_fitted ? "auto" : "fixed"},
                           {"x", {soil.mesh.x_min_m, soil.mesh.x_max_m}},
                           {"y", {soil.mesh.y_min_m, soil.mesh.y_max_m}},
                           {"depth", soil.mesh.depth_m}};
  // The layouts the nodes will publish: what a stream of this scenario is checked against.
  nlohmann::json surface = nlohmann::json::array();
  for (const auto& r : soil.receivers)
    surface.push_back({{"name", r.name}, {"x_m", r.x_m}, {"y_m", r.y_m}, {"z_m", r.z_m}});
  summary["layouts"] = {{"sleeper_x_m", track.layout.sleeperPositions()},
                        {"sleeper_length_m", track.layout.length_m},
                        {"sleeper_width_m", track.layout.width_m},
                        {"wheels", vehicle_params.axleOffsets().size()},
                        {"surface_points", surface},
                        {"building_points", house_points}};
  return summary;
}

}  // namespace railvib::scenario
