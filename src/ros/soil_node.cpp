#include "railvib/ros/soil_node.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "railvib/PointLayout.h"
#include "railvib/building/model.hpp"
#include "railvib/building/params.hpp"
#include "railvib/common/names.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/coupling/house_foundation.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/scenario/scenario.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::ros_io {

namespace {

// What every rank needs to build the same soil model: the merged scenario and one node parameter.
std::string setupText(const Config& config, bool include_footprint) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "include_building_footprint" << YAML::Value << include_footprint << YAML::Key
      << "config_file" << YAML::Value << YAML::DoubleQuoted << config.file() << YAML::Key << "config" << YAML::Value
      << YAML::Literal << config.dump() << YAML::EndMap;
  return out.c_str();
}

struct SoilSetup {
  soil::SoilParams params;
  std::vector<soil::RigidBodySpec> bodies;  // a two-way house's foundation
  double load_sample_rate_hz = 0.0;
  std::vector<double> rail_seat_y_m;  // the rail seats whose forces come one by one (none: half track)
};

SoilSetup soilSetup(const ConfigNode& root, bool include_footprint) {
  SoilSetup s;
  s.params = soil::loadSoilParams(root, coupling::houseReceivers(root, include_footprint));
  // building.coupling two_way: the house's foundation is a rigid body in the soil (when the house is in the run).
  if (include_footprint) s.bodies = coupling::attachHouse(root, s.params);
  const track::TrackParams track_params = track::loadTrackParams(root);
  s.load_sample_rate_hz = track_params.load_sample_rate_hz;
  s.rail_seat_y_m = track::soilRailSeatPositions(track_params);
  return s;
}

}  // namespace

soil::SoilDriver::Factory SoilNode::modelFactory() {
  return [](const std::string& setup, const std::vector<double>& sleeper_x_m, std::shared_ptr<soil::SoilComm> comm) {
    const YAML::Node s = YAML::Load(setup);
    const Config config = Config::fromString(s["config"].as<std::string>(), s["config_file"].as<std::string>());
    const SoilSetup soil_setup = soilSetup(config.root(), s["include_building_footprint"].as<bool>());
    return std::make_unique<soil::SoilModel>(soil_setup.params, sleeper_x_m, soil_setup.rail_seat_y_m,
                                             soil_setup.load_sample_rate_hz, soil_setup.bodies, std::move(comm));
  };
}

int SoilNode::serveOtherRank(std::shared_ptr<soil::SoilComm> comm) {
  try {
    return soil::SoilDriver::serve(comm, modelFactory());
  } catch (const std::exception& e) {
    // Rank 0 cannot go on without this rank's slab: stop the whole run with the reason.
    comm->abort("soil rank " + std::to_string(comm->rank()) + ": " + e.what(), 1);
  }
  return 1;  // not reached (abort ends the process), for compilers that miss [[noreturn]] on a virtual call
}

SoilNode::SoilNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, std::shared_ptr<soil::SoilComm> comm)
    : driver_(std::move(comm), modelFactory()) {
  const Config config = loadNodeConfig(nh);
  bool include_footprint = true;
  int required_subscribers = 1;
  private_nh.param("include_building_footprint", include_footprint, include_footprint);
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  const SoilSetup setup = soilSetup(config.root(), include_footprint);
  params_ = setup.params;
  load_sample_rate_hz_ = setup.load_sample_rate_hz;
  rail_seat_y_m_ = setup.rail_seat_y_m;
  setup_ = setupText(config, include_footprint);
  if (include_footprint) {
    for (const std::string& note : scenario::soilSensorsOnTheFoundation(config.root(), params_.receivers))
      ROS_WARN("soil: %s", note.c_str());
  }
  limits_ = loadStreamLimits(config.root());
  status_ = std::make_unique<NodeStatus>(nh, "soil", vehicle::loadPassageParams(config.root()).duration_s);
  velocity_publisher_ =
      BlockPublisher<railvib::SurfaceVelocities>(nh, names::kSurfaceVelocitiesTopic, required_subscribers);
  layout_publisher_ = nh.advertise<railvib::PointLayout>(names::kSurfacePointsTopic, 1, true);
  snapshot_publisher_ = nh.advertise<railvib::SurfaceSnapshot>(names::kSurfaceSnapshotTopic, 0);
  if (params_.section_enabled) {
    section_publisher_ = nh.advertise<railvib::SectionSnapshot>(names::kSectionSnapshotTopic, 0);
  }
  layout_subscriber_ = nh.subscribe(names::kSleeperLayoutTopic, 1, &SoilNode::onLayout, this);
  loads_subscriber_ = nh.subscribe(names::kSoilLoadsTopic, 0, &SoilNode::onLoads, this);
}

void SoilNode::onLayout(const railvib::SleeperLayout::ConstPtr& layout) {
  if (driver_.created()) return;
  status_->guard([&] {
    const std::string topic = layout_subscriber_.getTopic();
    // !(|d| <= tol) refuses NaN too.
    if (!(std::abs(layout->length_m - params_.track.length_m) <= 1e-9) ||
        !(std::abs(layout->width_m - params_.track.width_m) <= 1e-9)) {
      throw StreamContractError("stream " + topic + ": sleeper footprint length_m = " + formatValue(layout->length_m) +
                                ", width_m = " + formatValue(layout->width_m) + " differs from track.sleeper (" +
                                formatValue(params_.track.length_m) + " x " + formatValue(params_.track.width_m) +
                                " m; the same config is expected)");
    }
    validateSleeperPositions(topic, layout->position_m, limits_.max_points);
    const std::vector<double> expected = params_.track.sleeperPositions();
    if (layout->position_m.size() != expected.size()) {
      throw StreamContractError("stream " + topic + ": " + std::to_string(layout->position_m.size()) +
                                " sleepers, the track config (track.sleeper, track.extent) has " +
                                std::to_string(expected.size()));
    }
    for (size_t i = 0; i < expected.size(); ++i) {
      if (!(std::abs(layout->position_m[i] - expected[i]) <= 1e-6)) {
        throw StreamContractError("stream " + topic + ": position_m[" + std::to_string(i) +
                                  "] = " + formatValue(layout->position_m[i]) + " m, the track config puts it at " +
                                  formatValue(expected[i]) + " m");
      }
    }
    // The rail seats whose forces SoilLoads carries one by one: the config's (none for the half track).
    if (layout->rail_seat_y_m.size() != rail_seat_y_m_.size()) {
      throw StreamContractError(
          "stream " + topic + ": " + std::to_string(layout->rail_seat_y_m.size()) +
          " rail seats (rail_seat_y_m), the track config (track.width = " + (rail_seat_y_m_.empty() ? "half" : "full") +
          ") has " + std::to_string(rail_seat_y_m_.size()));
    }
    for (size_t i = 0; i < rail_seat_y_m_.size(); ++i) {
      if (!(std::abs(layout->rail_seat_y_m[i] - rail_seat_y_m_[i]) <= 1e-9)) {
        throw StreamContractError("stream " + topic + ": rail_seat_y_m[" + std::to_string(i) + "] = " +
                                  formatValue(layout->rail_seat_y_m[i]) + " m, the track config puts the seat at " +
                                  formatValue(rail_seat_y_m_[i]) + " m (site.rail_gauge_m / 2)");
      }
    }
    driver_.create(setup_, layout->position_m);
    const soil::SoilModel& model = driver_.model();
    ROS_INFO_STREAM("soil: " << model.summary().dump());
    if (!model.droppedSleepers().empty()) ROS_WARN_STREAM("soil: " << model.droppedLoadsNote());
    railvib::PointLayout points;
    points.header.frame_id = names::kTrackFrame;
    for (const auto& r : model.receivers()) {
      points.names.push_back(r.name);
      geometry_msgs::Point p;
      p.x = r.x_m;
      p.y = r.y_m;
      p.z = r.z_m;
      points.positions.push_back(p);
    }
    layout_publisher_.publish(points);
    gate_.open();
  });
}

void SoilNode::onLoads(const railvib::SoilLoads::ConstPtr& msg) {
  gate_.run([this, msg] {
    status_->guard([&] {
      if (ended_) {
        throw StreamContractError("stream " + loads_subscriber_.getTopic() + ": a block (first_sample_index " +
                                  std::to_string(msg->first_sample_index) + ") after the end_of_stream block");
      }
      consume(*msg);
    });
  });
}

void SoilNode::consume(const railvib::SoilLoads& msg) {
  if (!driver_.created()) throw std::runtime_error("soil loads arrived before the sleeper layout");
  const soil::SoilModel& model = driver_.model();
  BlockContract contract;
  contract.stream = loads_subscriber_.getTopic();
  contract.sample_period_s = 1.0 / load_sample_rate_hz_;
  contract.period_source = "track.output.load_sample_rate_hz = " + formatValue(load_sample_rate_hz_) + " Hz";
  contract.count_field = "sleeper_count";
  contract.point_label = "sleeper";
  contract.point_count = static_cast<uint32_t>(model.sleeperCount());
  contract.point_source = "the sleeper_layout";
  contract.max_block_samples = limits_.max_block_samples;
  const uint32_t seats = static_cast<uint32_t>(model.loadsPerSleeper());
  if (msg.seats_per_sleeper != seats) {
    throw StreamContractError("stream " + contract.stream + ": seats_per_sleeper = " +
                              std::to_string(msg.seats_per_sleeper) + ": the sleeper_layout has " +
                              (seats == 1 ? std::string("no rail seats (half track: one force per sleeper)")
                                          : std::to_string(seats) + " rail seats per sleeper") +
                              " (block at sample " + std::to_string(msg.first_sample_index) + ")");
  }
  validateBlock(
      contract,
      {msg.first_sample_index, msg.end_of_stream != 0, msg.sample_period_s, msg.sample_count, msg.sleeper_count},
      {{"force_n", &msg.force_n, seats, limits_.soil_load_n, "limits.soil_load_n", "N"}});
  driver_.pushLoads(msg.first_sample_index, msg.force_n.data(), msg.sample_count);
  status_->countSamples("soil_loads in", msg.sample_count);
  if (msg.end_of_stream) {
    driver_.finishLoads();
    const double t_end = static_cast<double>(msg.first_sample_index + msg.sample_count - 1) * msg.sample_period_s;
    // Step in slices so outputs and progress flow while the soil catches up.
    driver_.finishRun(t_end, 0.05, [this, &model] {
      publishOutputs(false);
      status_->update(model.time());
      return ros::ok();
    });
    ended_ = true;
    publishOutputs(true);
    status_->finish(model.time());
    return;
  }
  driver_.advance(model.loadsAvailableUntil());
  publishOutputs(false);
  status_->update(model.time());
}

void SoilNode::publishOutputs(bool end_of_stream) {
  const soil::SoilModel& model = driver_.model();
  driver_.takeOutputs(receivers_, snapshots_, sections_);
  const size_t frames = receivers_.frames();
  if (frames > 0 || end_of_stream) {
    if (frames > 0 && receivers_.first_index != next_velocity_index_) {
      throw std::runtime_error("soil receiver frames are not contiguous");
    }
    railvib::SurfaceVelocities block;
    block.header.frame_id = names::kTrackFrame;
    block.header.stamp = ros::Time(static_cast<double>(next_velocity_index_) / params_.receiver_rate_hz);
    block.first_sample_index = next_velocity_index_;
    block.end_of_stream = end_of_stream;
    block.sample_period_s = 1.0 / params_.receiver_rate_hz;
    block.sample_count = static_cast<uint32_t>(frames);
    block.receiver_count = static_cast<uint32_t>(model.receivers().size());
    block.velocity_m_s = receivers_.velocity_m_s;
    velocity_publisher_.publish(block);
    next_velocity_index_ += frames;
    status_->countSamples("surface_velocities out", frames);
  }
  for (const auto& s : snapshots_) {
    railvib::SurfaceSnapshot msg;
    msg.header.frame_id = names::kTrackFrame;
    msg.header.stamp = ros::Time(s.time_s);
    msg.sample_index = s.index;
    msg.origin_x_m = s.x0_m;
    msg.origin_y_m = s.y0_m;
    msg.spacing_x_m = s.dx_m;
    msg.spacing_y_m = s.dy_m;
    msg.nx = static_cast<uint32_t>(s.nx_nodes);
    msg.ny = static_cast<uint32_t>(s.ny_nodes);
    msg.vertical_velocity_m_s = s.vz_up_m_s;
    msg.velocity_x_m_s = s.vx_m_s;
    msg.velocity_y_m_s = s.vy_m_s;
    snapshot_publisher_.publish(msg);
  }
  for (const auto& s : sections_) {
    railvib::SectionSnapshot msg;
    msg.header.frame_id = names::kTrackFrame;
    msg.header.stamp = ros::Time(s.time_s);
    msg.sample_index = s.index;
    msg.x_m = s.x_m;
    msg.origin_y_m = s.y0_m;
    msg.spacing_y_m = s.dy_m;
    msg.ny = static_cast<uint32_t>(s.ny_nodes);
    msg.depth_m = s.depth_m;
    msg.vertical_velocity_m_s = s.vz_up_m_s;
    msg.velocity_x_m_s = s.vx_m_s;
    msg.velocity_y_m_s = s.vy_m_s;
    section_publisher_.publish(msg);
  }
}

}  // namespace railvib::ros_io
