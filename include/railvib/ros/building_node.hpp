// railvib ROS layer: building node. Takes the soil velocities at the house
// footprint receivers (SurfaceVelocities + latched PointLayout), drives the
// house model (railvib::building::BuildingResponseSolver) and publishes
// BuildingResponse blocks at the response points, with their latched
// PointLayout (`building_points`, positions in frame track).
#pragma once

#include <ros/ros.h>

#include <memory>
#include <vector>

#include "railvib/BuildingResponse.h"
#include "railvib/PointLayout.h"
#include "railvib/SurfaceVelocities.h"
#include "railvib/building/model.hpp"
#include "railvib/building/response.hpp"
#include "railvib/common/sample_stream.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/ros/block_publisher.hpp"
#include "railvib/ros/layout_gate.hpp"
#include "railvib/ros/node_status.hpp"

namespace railvib::ros_io {

class BuildingNode {
 public:
  /// Private parameters: ~required_subscribers (default 1).
  BuildingNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  bool failed() const { return status_->failed(); }

 private:
  void onLayout(const railvib::PointLayout::ConstPtr& layout);
  void onVelocities(const railvib::SurfaceVelocities::ConstPtr& msg);
  void consume(const railvib::SurfaceVelocities& msg);

  std::unique_ptr<building::BuildingModel> model_;
  std::unique_ptr<building::BuildingResponseSolver> solver_;
  std::vector<building::FootprintPoint> footprint_;
  std::vector<size_t> receiver_of_footprint_;  // soil receiver index of each footprint point
  uint32_t receiver_count_ = 0;                // receivers of the surface_points layout
  double receiver_rate_hz_ = 0.0;              // soil.output.receiver_rate_hz
  StreamLimits limits_;
  SampleIndexTracker tracker_{"surface_velocities"};
  LayoutGate gate_;              // velocities wait for the receiver layout
  BuildingPlacement placement_;  // frame building in frame track
  BlockPublisher<railvib::BuildingResponse> publisher_;
  ros::Publisher layout_publisher_;
  ros::Subscriber layout_subscriber_, velocity_subscriber_;
  std::unique_ptr<NodeStatus> status_;
  bool ended_ = false;
};

}  // namespace railvib::ros_io
