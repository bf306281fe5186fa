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

#include "railvib/SectionSnapshot.h"
#include "railvib/SleeperLayout.h"
#include "railvib/SoilLoads.h"
#include "railvib/SurfaceSnapshot.h"
#include "railvib/SurfaceVelocities.h"
#include "railvib/common/stream_contract.hpp"
#include "railvib/ros/block_publisher.hpp"
#include "railvib/ros/layout_gate.hpp"
#include "railvib/ros/node_status.hpp"
#include "railvib/soil/soil_driver.hpp"
#include "railvib/soil/soil_model.hpp"

namespace railvib::ros_io {

class SoilNode {
 public:
  /// Private parameters: ~include_building_footprint (default true: the house's footprint points
  /// become receivers), ~required_subscribers (surface_velocities, default 1).
  /// comm: the MPI ranks the soil is spread over (this node is rank 0; null = one rank).
  SoilNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, std::shared_ptr<soil::SoilComm> comm = nullptr);
  /// The soil node's ranks other than 0 (under mpirun): no ROS, they build and step their slabs as
  /// rank 0's node says (soil::SoilDriver); aborts the run with the reason if their model fails.
  static int serveOtherRank(std::shared_ptr<soil::SoilComm> comm);
  /// The soil model of every rank, from the setup text rank 0 sends (the merged scenario).
  static soil::SoilDriver::Factory modelFactory();
  bool failed() const { return status_->failed(); }

 private:
  void onLayout(const railvib::SleeperLayout::ConstPtr& layout);
  void onLoads(const railvib::SoilLoads::ConstPtr& msg);
  void consume(const railvib::SoilLoads& msg);
  void publishOutputs(bool end_of_stream);

  soil::SoilParams params_;
  soil::SoilDriver driver_;
  std::string setup_;  // what the model of every rank is built from (modelFactory)
  double load_sample_rate_hz_ = 0.0;
  std::vector<double> rail_seat_y_m_;  // the track's rail seats (track::soilRailSeatPositions)
  StreamLimits limits_;
  BlockPublisher<railvib::SurfaceVelocities> velocity_publisher_;
  ros::Publisher layout_publisher_, snapshot_publisher_, section_publisher_;
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
