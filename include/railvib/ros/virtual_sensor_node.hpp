// railvib ROS layer: virtual sensor node. Takes the soil receivers'
// SurfaceVelocities and the building's BuildingResponse (with their latched
// PointLayout), runs one railvib::signal::VirtualSensor per configured sensor
// and publishes, per sensor, one sample per message:
//   sensors/<name>/imu       sensor_msgs/Imu (acceleration; REP 145 gravity option)
//   sensors/<name>/velocity  geometry_msgs/Vector3Stamped (m/s)
//   sensors/<name>/metrics   railvib/VibrationMetrics (metrics_rate_hz of simulated time; also on
//                            `sensor_metrics` for all sensors, and once more at the end of the record)
// plus /diagnostics, and the lossless block stream `sensor_samples`. Private parameters:
// ~required_subscribers (sensor_samples, default 1), ~sensor_topic_subscribers (each sensor's own
// topics, default 0; 1 when a recorder records them), ~use_building, ~publish_clock, ~block_samples.
#pragma once

#include <geometry_msgs/Vector3Stamped.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "railvib/PointLayout.h"
#include "railvib/SensorSamples.h"
#include "railvib/VibrationMetrics.h"
#include "railvib/common/sample_stream.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/ros/block_publisher.hpp"
#include "railvib/ros/layout_gate.hpp"
#include "railvib/ros/node_status.hpp"
#include "railvib/signal/virtual_sensor.hpp"

namespace railvib::ros_io {

class VirtualSensorNode {
 public:
  /// Private parameters: ~use_building (default true), ~required_subscribers (sensor_samples, default 1),
  /// ~block_samples (sensor_samples block length, default 100), ~publish_clock (default false: publish
  /// /clock at the newest sample any sensor has emitted, for a live graph run with /use_sim_time).
  VirtualSensorNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// True after an error (gap in a stream, unknown point...); the node has shut ROS down.
  bool failed() const { return status_->failed(); }

  /// One input stream's block (SurfaceVelocities or BuildingResponse share this layout).
  struct InputBlock {
    uint64_t first_sample_index = 0;
    bool end_of_stream = false;
    double sample_period_s = 0.0;
    uint32_t sample_count = 0;
    uint32_t point_count = 0;
    const std::vector<double>* velocity_m_s = nullptr;
  };

 private:
  struct Sensor {
    signal::VirtualSensorSetup setup;
    std::unique_ptr<signal::VirtualSensor> sensor;
    int point_index = -1;
    // Each sensor's own topics wait, like the streams, for ~sensor_topic_subscribers before their first
    // message: a recorder of these topics connects to each one apart, and would miss the first samples.
    BlockPublisher<sensor_msgs::Imu> imu;
    BlockPublisher<geometry_msgs::Vector3Stamped> velocity;
    BlockPublisher<railvib::VibrationMetrics> metrics;
    std::vector<signal::SensorSample> pending;  // emitted, not yet in a sensor_samples block
    std::vector<signal::SensorSample> fresh;    // emitted by the block being handled
    uint64_t published = 0;
    double latest_time_s = -1.0;  // time of the newest emitted sample (-1: none yet)
  };
  struct Source {
    std::string name;
    std::unique_ptr<SampleIndexTracker> tracker;
    std::vector<std::string> point_names;
    std::string count_field;  // the block's point count field
    std::string layout_name;  // its latched layout, for messages
    bool ended = false;
    LayoutGate gate;  // blocks wait for the latched point layout
    ros::Subscriber layout_sub, data_sub;
  };

  void onLayout(Source& source, const railvib::PointLayout& layout);
  void onBlock(Source& source, const InputBlock& block);
  void publishSamples(Sensor& s, const std::vector<signal::SensorSample>& samples, size_t from);
  void publishMetrics(Sensor& s, double time_s);
  void publishBlocks(bool end_of_stream);
  void restartPass(Source& source);
  void publishClock();

  signal::VirtualSensorConfig config_;
  StreamLimits limits_;
  double input_rate_hz_ = 0.0;  // soil.output.receiver_rate_hz: both sources run at it
  double resolved_hz_ = 0.0;    // soil.mesh.f_max_hz: verdicts governed above it are not assessable
  std::vector<Sensor> sensors_;
  std::vector<std::unique_ptr<Source>> sources_;
  BlockPublisher<railvib::SensorSamples> samples_publisher_;
  ros::Publisher diagnostics_publisher_;
  ros::Publisher all_metrics_publisher_;
  ros::Publisher clock_publisher_;  // only with ~publish_clock
  double clock_s_ = -1.0;           // last /clock published
  size_t block_samples_ = 100;
  uint64_t next_block_index_ = 0;
  uint64_t metrics_every_ = 100;
  std::unique_ptr<NodeStatus> status_;
  bool finished_ = false;
};

}  // namespace railvib::ros_io
