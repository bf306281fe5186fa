#include "railvib/ros/moving_load_source.hpp"

#include <cmath>

#include "railvib/common/names.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/ros/wheel_rails.hpp"
#include "railvib/vehicle/vehicle_model.hpp"

namespace railvib::ros_io {

MovingLoadSourceNode::MovingLoadSourceNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  const vehicle::PassageParams run = vehicle::loadPassageParams(config.root());
  dt_s_ = run.time_step_s;
  total_samples_ = static_cast<uint64_t>(std::llround(run.duration_s / dt_s_)) + 1;
  source_.front_start_m = run.front_axle_start_m;
  source_.speed_m_s = run.speed_m_s;
  const vehicle::VehicleModel vehicle_model(vehicle::loadVehicleParams(config.root()));
  // Each wheel's share of the weight on its rail (the weight per rail shared by the axles), on its rail.
  const std::vector<double> per_axle = vehicle::uniformStaticWheelLoadsPerRail(vehicle_model);
  for (const vehicle::WheelInfo& w : vehicle_model.wheels()) {
    source_.offsets_behind_m.push_back(w.offset_m);
    source_.forces_n.push_back(per_axle.at(static_cast<size_t>(w.axle)));
  }
  source_.rails = vehicle_model.wheelRails();
  wheel_rail_ = wheelRailCodes(source_.rails);
  int block_samples = 1000;
  int required_subscribers = 1;
  private_nh.param("block_samples", block_samples, block_samples);
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  block_samples_ = static_cast<size_t>(std::max(1, block_samples));
  publisher_ = BlockPublisher<railvib::ContactForces>(nh, names::kContactForcesTopic, required_subscribers);
}

void MovingLoadSourceNode::run() {
  const size_t wheels = source_.offsets_behind_m.size();
  for (uint64_t first = 0; first < total_samples_ && ros::ok(); first += block_samples_) {
    const size_t count = static_cast<size_t>(std::min<uint64_t>(block_samples_, total_samples_ - first));
    railvib::ContactForces block;
    block.header.frame_id = names::kTrackFrame;
    block.header.stamp = ros::Time(static_cast<double>(first) * dt_s_);
    block.first_sample_index = first;
    block.end_of_stream = first + count == total_samples_;
    block.sample_period_s = dt_s_;
    block.sample_count = static_cast<uint32_t>(count);
    block.wheel_count = static_cast<uint32_t>(wheels);
    block.wheel_rail = wheel_rail_;
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
