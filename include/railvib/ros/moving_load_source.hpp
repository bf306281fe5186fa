// railvib ROS layer: constant moving wheel loads published as ContactForces,
// the stand-in for the vehicle in the track scenario (track.launch): one per
// axle (half track) or per wheel on its rail (full width).
#pragma once

#include <ros/ros.h>

#include <vector>

#include "railvib/ContactForces.h"
#include "railvib/ros/block_publisher.hpp"
#include "railvib/track/track_stepper.hpp"

namespace railvib::ros_io {

class MovingLoadSourceNode {
 public:
  /// Private parameters: ~block_samples (default 1000), ~required_subscribers (default 1).
  MovingLoadSourceNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// Publish the whole run, block by block (returns when done or on shutdown).
  void run();

 private:
  track::MovingLoadSource source_;
  std::vector<uint8_t> wheel_rail_;  // ContactForces.wheel_rail
  double dt_s_ = 0.0;
  uint64_t total_samples_ = 0;
  size_t block_samples_ = 1000;
  BlockPublisher<railvib::ContactForces> publisher_;
};

}  // namespace railvib::ros_io
