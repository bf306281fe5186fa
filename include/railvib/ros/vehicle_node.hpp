// railvib ROS layer: vehicle node. Runs the coupled vehicle/track passage
// (railvib::vehicle::VehiclePassage) block by block and publishes
// ContactForces blocks and the tram's body poses on tf (frames tram/<body>,
// stamped with simulation time), with progress on the console and /diagnostics.
#pragma once

#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>

#include <memory>
#include <vector>

#include "railvib/ContactForces.h"
#include "railvib/ros/block_publisher.hpp"
#include "railvib/ros/node_status.hpp"
#include "railvib/vehicle/passage.hpp"

namespace railvib::ros_io {

class VehicleNode {
 public:
  /// The rail under the vehicle is simulation.vehicle_track (config). Private parameters:
  /// ~block_samples (default 1000),
  /// ~required_subscribers (default 1), ~tf_period_s (simulated time between tf poses, default 0.01),
  /// ~tf_required_subscribers (subscribers of /tf to wait for before the first pose, e.g. the
  /// recorder, default 0: then a late listener misses the first poses).
  VehicleNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// Run the whole passage (returns when done or on shutdown).
  void run();

 private:
  void publishPoses(const vehicle::PassageBlock& block);

  std::unique_ptr<vehicle::VehicleModel> model_;
  std::unique_ptr<vehicle::Unevenness> unevenness_;
  std::unique_ptr<vehicle::VehiclePassage> passage_;
  BlockPublisher<railvib::ContactForces> publisher_;
  BlockPublisher<tf2_msgs::TFMessage> tf_publisher_;
  std::unique_ptr<NodeStatus> status_;
  std::vector<uint8_t> wheel_rail_;  // ContactForces.wheel_rail: the rail under each wheel
  size_t block_samples_ = 1000;
  uint64_t tf_every_ = 1000;
};

}  // namespace railvib::ros_io
