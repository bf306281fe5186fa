// railvib ROS layer: replay of a recorded railvib bag as live streams, paced
// by the recorded simulation time (optionally faster or slower, optionally
// looping), like field sensors streaming to a monitoring station. Latched
// description topics (PointLayout, SleeperLayout) are republished latched;
// /clock follows the replayed time. A truncated or corrupt bag is refused
// with a clear error before anything is published.
#pragma once

#include <ros/ros.h>
#include <rosbag/bag.h>

#include <map>
#include <string>
#include <vector>

namespace railvib::ros_io {

class BagReplay {
 public:
  /// Private parameters: ~bag, ~rate (default 1.0), ~loop (default false), ~topics (default: all),
  /// ~required_subscribers (on the first stream topic, default 1), ~publish_clock (default true),
  /// ~start_delay_s (wall seconds between advertising and the first message, default 0: time for
  /// late subscribers such as RViz or a monitoring tool to connect).
  BagReplay(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// Replay (loops until shutdown when ~loop is set). Throws on a read error.
  void run();

 private:
  void playOnce(bool first_pass);

  ros::NodeHandle nh_;
  std::string bag_path_;
  double rate_ = 1.0;
  bool loop_ = false;
  bool publish_clock_ = true;
  int required_subscribers_ = 1;
  double start_delay_s_ = 0.0;
  std::vector<std::string> topics_;
  rosbag::Bag bag_;
  std::map<std::string, ros::Publisher> publishers_;
  ros::Publisher clock_publisher_;
};

}  // namespace railvib::ros_io
