#include "railvib/ros/soil_node.hpp"

#include <algorithm>

#include "railvib/PointLayout.h"
#include "railvib/building/model.hpp"
#include "railvib/building/params.hpp"
#include "railvib/common/names.hpp"
#include "railvib/coupling/house_foundation.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::ros_io {

SoilNode::SoilNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  bool include_footprint = true;
  int required_subscribers = 1;
  private_nh.param("include_building_footprint", include_footprint, include_footprint);
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  params_ = soil::loadSoilParams(config.root(), houseReceivers(config.root(), include_footprint));
  // building.coupling two_way: the house's foundation is a rigid body in the soil (when the house is in the run).
  if (include_footprint) bodies_ = coupling::attachedBodies(config.root(), params_);
  load_sample_rate_hz_ = track::loadTrackParams(config.root()).load_sample_rate_hz;
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

soil::HouseReceivers SoilNode::houseReceivers(const ConfigNode& root, bool include_footprint) {
  soil::HouseReceivers house;
  if (!root.has("building")) return house;
  const building::BuildingParams params = building::loadBuildingParams(root);
  house.free_field = building::freeFieldPoints(params);
  // The house is driven at its foundation nodes: each becomes a soil receiver.
  if (include_footprint) {
    for (const auto& f : building::footprintPoints(params)) {
      house.footprint.push_back({f.name, f.x_track_m, f.y_track_m, f.z_track_m});
    }
  }
  return house;
}

void SoilNode::onLayout(const railvib::SleeperLayout::ConstPtr& layout) {
  if (model_) return;
  status_->guard([&] {
    if (std::abs(layout->length_m - params_.track.length_m) > 1e-9 ||
        std::abs(layout->width_m - params_.track.width_m) > 1e-9) {
      throw std::runtime_error("the track's sleeper footprint differs from the soil's (same config expected)");
    }
    model_ = std::make_unique<soil::SoilModel>(params_, layout->position_m, load_sample_rate_hz_, bodies_);
    ROS_INFO_STREAM("soil: " << model_->summary().dump());
    if (!model_->droppedSleepers().empty()) {
      ROS_WARN("soil: %zu sleeper(s) outside the mesh: their loads are ignored", model_->droppedSleepers().size());
    }
    railvib::PointLayout points;
    points.header.frame_id = names::kTrackFrame;
    for (const auto& r : model_->receivers()) {
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
    if (!ended_) status_->guard([&] { consume(*msg); });
  });
}

void SoilNode::consume(const railvib::SoilLoads& msg) {
  if (!model_) throw std::runtime_error("soil loads arrived before the sleeper layout");
  if (msg.sleeper_count != model_->sleeperCount() ||
      msg.force_n.size() != static_cast<size_t>(msg.sample_count) * msg.sleeper_count) {
    throw std::runtime_error("malformed SoilLoads block (sleeper count differs from the layout)");
  }
  if (std::abs(msg.sample_period_s * load_sample_rate_hz_ - 1.0) > 1e-9) {
    throw std::runtime_error("soil loads come every " + std::to_string(msg.sample_period_s) +
                             " s, not at track.output.load_sample_rate_hz = " + std::to_string(load_sample_rate_hz_) +
                             " Hz");
  }
  model_->pushLoads(msg.first_sample_index, msg.force_n.data(), msg.sample_count);
  status_->countSamples("soil_loads in", msg.sample_count);
  if (msg.end_of_stream) {
    model_->finishLoads();
    const double t_end = static_cast<double>(msg.first_sample_index + msg.sample_count - 1) * msg.sample_period_s;
    // Step in slices so outputs and progress flow while the soil catches up.
    model_->finishRun(t_end, 0.05, [this] {
      publishOutputs(false);
      status_->update(model_->time());
      return ros::ok();
    });
    ended_ = true;
    publishOutputs(true);
    status_->finish(model_->time());
    return;
  }
  model_->advance(model_->loadsAvailableUntil());
  publishOutputs(false);
  status_->update(model_->time());
}

void SoilNode::publishOutputs(bool end_of_stream) {
  model_->takeReceiverSamples(receivers_);
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
    block.receiver_count = static_cast<uint32_t>(model_->receivers().size());
    block.velocity_m_s = receivers_.velocity_m_s;
    velocity_publisher_.publish(block);
    next_velocity_index_ += frames;
    status_->countSamples("surface_velocities out", frames);
  }
  snapshots_.clear();
  model_->takeSnapshots(snapshots_);
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
    snapshot_publisher_.publish(msg);
  }
  sections_.clear();
  model_->takeSectionSnapshots(sections_);
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
    section_publisher_.publish(msg);
  }
}

}  // namespace railvib::ros_io
