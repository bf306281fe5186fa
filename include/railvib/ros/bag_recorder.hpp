// railvib ROS layer: in-process bag recorder.
//
// Records the given topics into one bag with LZ4 compression, each message at
// the time of its header stamp (simulation time), so `rosbag play --clock`
// replays at true simulated speed. tf topics (/tf, /tf_static) are recorded
// at the latest stamp of their transforms; static frames (stamp 0) go to the
// start of the bag. Stream topics (messages that begin with
// Header, first_sample_index, end_of_stream, sample_period_s, sample_count)
// are checked for continuity; the bag is closed and the node exits once every
// stream has delivered its end_of_stream block (plus ~linger_s for messages
// still in flight on other topics). On a gap, or on shutdown, the
// bag is closed cleanly (readable) and the reason is logged.
#pragma once

#include <ros/ros.h>
#include <rosbag/bag.h>
#include <topic_tools/shape_shifter.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "railvib/common/sample_stream.hpp"

namespace railvib::ros_io {

class BagRecorder {
 public:
  /// Parameters (private): ~bag_path, ~streams (list), ~topics (list, header-stamped),
  /// ~tf_topics (list of tf2_msgs/TFMessage topics), ~compression (lz4|none), ~linger_s.
  BagRecorder(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  ~BagRecorder();

  /// Close the bag once every stream is complete and ~linger_s (default 1 s wall) has passed.
  void poll();
  bool finished() const { return finished_; }
  bool failed() const { return failed_; }
  /// Close the bag (idempotent) and print per-topic counts.
  void close(const std::string& reason);

 private:
  struct TopicState {
    bool is_stream = false;
    bool is_tf = false;
    std::unique_ptr<SampleIndexTracker> tracker;
    bool ended = false;
    uint64_t messages = 0;
    ros::Time first_stamp, last_stamp;
  };
  void onMessage(const std::string& topic, const ros::MessageEvent<topic_tools::ShapeShifter const>& event);

  rosbag::Bag bag_;
  std::string bag_path_;
  bool open_ = false;
  bool finished_ = false;
  bool failed_ = false;
  bool all_streams_complete_ = false;
  ros::WallTime all_streams_complete_at_;
  double linger_s_ = 1.0;
  std::map<std::string, TopicState> topics_;
  std::vector<ros::Subscriber> subscribers_;
  ros::Publisher status_publisher_;
};

}  // namespace railvib::ros_io
