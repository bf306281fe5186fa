#include "railvib/ros/moving_load_source.hpp"

#include <cmath>

#include "railvib/ros/node_config.hpp"

namespace railvib::ros_io {

MovingLoadSourceNode::MovingLoadSourceNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  const auto simulation = config.section("simulation");
  const auto vehicle = config.section("vehicle");
  dt_s_ = simulation.number("time_step_s", Range::positive());
  const double duration_s = simulation.number("duration_s", Range::positive());
  total_samples_ = static_cast<uint64_t>(std::llround(duration_s / dt_s_)) + 1;
  source_.front_start_m = simulation.number("front_axle_start_m", Range::any());
  source_.speed_m_s = simulation.number("speed_m_s", Range::nonNegative());
  source_.offsets_behind_m = vehicle.numbers("axle_offsets_m", Range::nonNegative(), 1);
  source_.forces_n = track::staticWheelLoadsPerRail(vehicle);
  int block_samples = 1000;
  int required_subscribers = 1;
  private_nh.param("block_samples", block_samples, block_samples);
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  block_samples_ = static_cast<size_t>(std::max(1, block_samples));
  publisher_ = BlockPublisher<railvib::ContactForces>(nh, "contact_forces", required_subscribers);
}

void MovingLoadSourceNode::run() {
  const size_t wheels = source_.offsets_behind_m.size();
  for (uint64_t first = 0; first < total_samples_ && ros::ok(); first += block_samples_) {
    const size_t count = static_cast<size_t>(std::min<uint64_t>(block_samples_, total_samples_ - first));
    railvib::ContactForces block;
    block.header.frame_id = "track";
    block.header.stamp = ros::Time(static_cast<double>(first) * dt_s_);
    block.first_sample_index = first;
    block.end_of_stream = first + count == total_samples_;
    block.sample_period_s = dt_s_;
    block.sample_count = static_cast<uint32_t>(count);
    block.wheel_count = static_cast<uint32_t>(wheels);
    block.position_m.reserve(count * wheels);
    block.force_n.reserve(count * wheels);
    block.unevenness_m.assign(count * wheels, 0.0);
    for (size_t s = 0; s < count; ++s) {
      for (const auto& load : source_.loadsAt(static_cast<double>(first + s) * dt_s_)) {
        block.position_m.push_back(load.x_m);
        block.force_n.push_back(load.force_n);
      }
    }
    publisher_.publish(block);
  }
}

}  // namespace railvib::ros_io
