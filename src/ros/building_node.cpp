#include "railvib/ros/building_node.hpp"

#include <algorithm>

#include "railvib/common/names.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::ros_io {

BuildingNode::BuildingNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  const building::BuildingParams params = building::loadBuildingParams(config.root());
  placement_ = params.placement;
  model_ = std::make_unique<building::BuildingModel>(params);
  footprint_ = building::footprintPoints(params);
  status_ = std::make_unique<NodeStatus>(nh, "building", vehicle::loadPassageParams(config.root()).duration_s);
  limits_ = loadStreamLimits(config.root());
  receiver_rate_hz_ = soil::loadReceiverRateHz(config.root());
  int required_subscribers = 1;
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  publisher_ = BlockPublisher<railvib::BuildingResponse>(nh, names::kBuildingResponseTopic, required_subscribers);
  layout_publisher_ = nh.advertise<railvib::PointLayout>(names::kBuildingPointsTopic, 1, true);
  layout_subscriber_ = nh.subscribe(names::kSurfacePointsTopic, 1, &BuildingNode::onLayout, this);
  velocity_subscriber_ = nh.subscribe(names::kSurfaceVelocitiesTopic, 0, &BuildingNode::onVelocities, this);
  ROS_INFO("building: %zu footprint points, mass %.0f kg", footprint_.size(), model_->totalMass());
}

void BuildingNode::onLayout(const railvib::PointLayout::ConstPtr& layout) {
  if (gate_.isOpen() || status_->failed()) return;
  status_->guard([&] {
    std::vector<double> xyz;
    for (const auto& p : layout->positions) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    validatePointLayout(layout_subscriber_.getTopic(), layout->names, layout->positions.size(), xyz,
                        limits_.max_points);
    receiver_of_footprint_.clear();
    for (const auto& f : footprint_) {
      const auto it = std::find(layout->names.begin(), layout->names.end(), f.name);
      if (it == layout->names.end()) {
        throw StreamContractError("stream " + layout_subscriber_.getTopic() + ": footprint point '" + f.name +
                                  "' is not among the soil receivers (soil must include the footprint)");
      }
      receiver_of_footprint_.push_back(static_cast<size_t>(it - layout->names.begin()));
    }
    receiver_count_ = static_cast<uint32_t>(layout->names.size());
    gate_.open();
  });
}

void BuildingNode::onVelocities(const railvib::SurfaceVelocities::ConstPtr& msg) {
  gate_.run([this, msg] {
    status_->guard([&] {
      if (ended_) {
        throw StreamContractError("stream " + velocity_subscriber_.getTopic() + ": a block (first_sample_index " +
                                  std::to_string(msg->first_sample_index) + ") after the end_of_stream block");
      }
      consume(*msg);
    });
  });
}

void BuildingNode::consume(const railvib::SurfaceVelocities& msg) {
  if (!gate_.isOpen()) throw std::runtime_error("surface velocities arrived before the receiver layout");
  // Counts, period and values against the layout and the config, before any index is used.
  BlockContract contract;
  contract.stream = velocity_subscriber_.getTopic();
  contract.sample_period_s = 1.0 / receiver_rate_hz_;
  contract.period_source = "soil.output.receiver_rate_hz = " + formatValue(receiver_rate_hz_) + " Hz";
  contract.count_field = "receiver_count";
  contract.point_label = "receiver";
  contract.point_count = receiver_count_;
  contract.point_source = "the surface_points layout";
  contract.max_block_samples = limits_.max_block_samples;
  validateBlock(
      contract,
      {msg.first_sample_index, msg.end_of_stream != 0, msg.sample_period_s, msg.sample_count, msg.receiver_count},
      {{"velocity_m_s", &msg.velocity_m_s, 3, limits_.velocity_m_s, "limits.velocity_m_s", "m/s"}});
  tracker_.accept(msg.first_sample_index, msg.sample_count);
  if (!solver_) {
    solver_ = std::make_unique<building::BuildingResponseSolver>(*model_, msg.sample_period_s);
    railvib::PointLayout layout;
    layout.header.frame_id = names::kTrackFrame;
    for (const auto& p : solver_->responsePoints()) {
      layout.names.push_back(p.name);
      geometry_msgs::Point q;
      q.x = placement_.trackX(p.position.x());
      q.y = placement_.trackY(p.position.y());
      q.z = p.position.z();
      layout.positions.push_back(q);
    }
    layout_publisher_.publish(layout);
  }
  // Footprint velocities, one row per sample, 3 columns per footprint point (frame axes are shared).
  Eigen::MatrixXd input(msg.sample_count, 3 * footprint_.size());
  for (uint32_t k = 0; k < msg.sample_count; ++k) {
    for (size_t f = 0; f < footprint_.size(); ++f) {
      const size_t base = (static_cast<size_t>(k) * msg.receiver_count + receiver_of_footprint_[f]) * 3;
      for (int c = 0; c < 3; ++c) input(k, static_cast<Eigen::Index>(3 * f + c)) = msg.velocity_m_s[base + c];
    }
  }
  const Eigen::MatrixXd output = solver_->process(msg.first_sample_index, input);
  railvib::BuildingResponse block;
  block.header.frame_id = names::kTrackFrame;
  block.header.stamp = msg.header.stamp;
  block.first_sample_index = msg.first_sample_index;
  block.end_of_stream = msg.end_of_stream;
  block.sample_period_s = msg.sample_period_s;
  block.sample_count = msg.sample_count;
  block.point_count = static_cast<uint32_t>(solver_->responsePoints().size());
  block.velocity_m_s.resize(static_cast<size_t>(output.size()));
  for (Eigen::Index k = 0; k < output.rows(); ++k) {
    for (Eigen::Index c = 0; c < output.cols(); ++c) block.velocity_m_s[k * output.cols() + c] = output(k, c);
  }
  publisher_.publish(block);
  status_->countSamples("surface_velocities in", msg.sample_count);
  status_->countSamples("building_response out", msg.sample_count);
  const double t = static_cast<double>(msg.first_sample_index + msg.sample_count) * msg.sample_period_s;
  ended_ = msg.end_of_stream;
  status_->update(t, ended_);
  if (ended_) status_->finish(t);
}

}  // namespace railvib::ros_io
