// railvib ROS layer: track node. Subscribes to ContactForces, runs the track
// (railvib::track::SoilLoadStream), publishes SoilLoads blocks and the latched
// SleeperLayout.
#pragma once

#include <ros/ros.h>

#include <memory>

#include "railvib/ContactForces.h"
#include "railvib/SoilLoads.h"
#include "railvib/common/sample_stream.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/ros/block_publisher.hpp"
#include "railvib/ros/node_status.hpp"
#include "railvib/track/soil_load_stream.hpp"

namespace railvib::ros_io {

class TrackNode {
 public:
  /// Private parameters: ~block_duration_s (default 0.05), ~required_subscribers (default 1).
  TrackNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// True after an error (gap in the input stream, mismatched step...); the node has shut ROS down.
  bool failed() const { return status_->failed(); }

 private:
  void onContactForces(const railvib::ContactForces::ConstPtr& msg);
  void consume(const railvib::ContactForces& block);
  void publishPending(bool end_of_stream);

  std::unique_ptr<track::SoilLoadStream> stream_;
  SampleIndexTracker tracker_{"contact_forces"};
  BlockPublisher<railvib::SoilLoads> loads_publisher_;
  ros::Publisher layout_publisher_;
  ros::Subscriber contact_subscriber_;
  std::vector<double> pending_;  // soil-load samples not yet published, [sample][sleeper][seat]
  uint64_t next_load_index_ = 0;
  size_t block_samples_ = 100;
  uint32_t wheel_count_ = 0;               // the vehicle's wheels (vehicles.<name>.wheels; per rail at full width)
  std::vector<track::Rail> wheel_rails_;   // the rail under each wheel, from the vehicle
  std::vector<uint8_t> wheel_rail_codes_;  // the same as ContactForces.wheel_rail carries it
  StreamLimits limits_;
  std::unique_ptr<NodeStatus> status_;
  bool ended_ = false;
};

}  // namespace railvib::ros_io
