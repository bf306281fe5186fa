// railvib ROS layer: lossless publication of stream blocks.
//
// Messages published before a subscriber connects are lost (ROS 1 design),
// and a full bounded publisher queue drops the oldest message. So a stream
// publisher advertises with an unbounded queue (queue_size 0) and, before its
// first block, waits until the expected number of subscribers (the recorder
// and the downstream nodes, from the launch file) are connected.
#pragma once

#include <ros/ros.h>

#include <string>

namespace railvib::ros_io {

template <class Msg>
class BlockPublisher {
 public:
  BlockPublisher() = default;
  /// required_subscribers: how many subscribers must be connected before the first publish.
  BlockPublisher(ros::NodeHandle& nh, const std::string& topic, int required_subscribers, bool latch = false)
      : publisher_(nh.advertise<Msg>(topic, 0, latch)), required_(required_subscribers) {}

  void publish(const Msg& msg) {
    if (!connected_) waitForSubscribers();
    publisher_.publish(msg);
  }

  /// Block until required subscribers are connected (or ROS shuts down).
  void waitForSubscribers() {
    const ros::WallTime start = ros::WallTime::now();
    ros::WallTime last_note = start;
    while (ros::ok() && static_cast<int>(publisher_.getNumSubscribers()) < required_) {
      if ((ros::WallTime::now() - last_note).toSec() > 5.0) {
        ROS_INFO("%s: waiting for %d subscriber(s), %u connected", publisher_.getTopic().c_str(), required_,
                 publisher_.getNumSubscribers());
        last_note = ros::WallTime::now();
      }
      ros::WallDuration(0.005).sleep();
    }
    connected_ = true;
  }

  std::string topic() const { return publisher_.getTopic(); }
  uint32_t subscriberCount() const { return publisher_.getNumSubscribers(); }

 private:
  ros::Publisher publisher_;
  int required_ = 0;
  bool connected_ = false;
};

}  // namespace railvib::ros_io
