// railvib ROS layer: soil node. Subscribes to SoilLoads (+ latched
// SleeperLayout), advances the soil model (railvib::soil::SoilModel) as far
// as the loads received allow (it may run behind them; it never drops any),
// publishes SurfaceVelocities blocks at the receivers with their latched
// PointLayout (`surface_points`), decimated SurfaceSnapshot messages and, with
// soil.output.section, SectionSnapshot messages of a vertical plane. With
// building.coupling two_way the house's foundation is part of the soil model
// (coupling/house_foundation.hpp): the footprint receivers then carry its motion.
#pragma once

#include <ros/ros.h>

#include <memory>

#include "railvib/SleeperLayout.h"
#include "railvib/SoilLoads.h"
#include "railvib/SectionSnapshot.h"
#include "railvib/SurfaceSnapshot.h"
#include "railvib/SurfaceVelocities.h"
#include "railvib/common/stream_contract.hpp"
#include "railvib/ros/block_publisher.hpp"
#include "railvib/ros/layout_gate.hpp"
#include "railvib/ros/node_status.hpp"
#include "railvib/soil/soil_model.hpp"

namespace railvib::ros_io {

class SoilNode {
 public:
  /// Private parameters: ~include_building_footprint (default true: the house's footprint points
  /// become receivers), ~required_subscribers (surface_velocities, default 1).
  SoilNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  bool failed() const { return status_->failed(); }

 private:
  void onLayout(const railvib::SleeperLayout::ConstPtr& layout);
  void onLoads(const railvib::SoilLoads::ConstPtr& msg);
  void consume(const railvib::SoilLoads& msg);
  void publishOutputs(bool end_of_stream);
  /// The house's receivers (free field, and footprint if asked), none without a `building` section.
  static soil::HouseReceivers houseReceivers(const ConfigNode& root, bool include_footprint);

  soil::SoilParams params_;
  std::unique_ptr<soil::SoilModel> model_;
  double load_sample_rate_hz_ = 0.0;
  StreamLimits limits_;
  BlockPublisher<railvib::SurfaceVelocities> velocity_publisher_;
  ros::Publisher layout_publisher_, snapshot_publisher_, section_publisher_;
  std::vector<soil::RigidBodySpec> bodies_;  // attached to the soil model (a two-way house's foundation)
  ros::Subscriber layout_subscriber_, loads_subscriber_;
  std::unique_ptr<NodeStatus> status_;
  soil::ReceiverBlock receivers_;
  LayoutGate gate_;  // loads wait for the sleeper layout
  std::vector<soil::SurfaceSnapshot> snapshots_;
  std::vector<soil::SectionSnapshot> sections_;
  uint64_t next_velocity_index_ = 0;
  bool ended_ = false;
};

}  // namespace railvib::ros_io
