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
//
// Results are never lost or overwritten: an existing bag_path is refused; before each write the
// recorder checks that the file system keeps ~min_free_mb (plus the index) free, and otherwise
// stops with "disk full" and closes the bag while it still can (indexed, readable, the streams
// reported incomplete); a write error closes it too. Closing writes a std_msgs/String (JSON) on
// names::kRecordingStatusTopic into the bag: the expected streams, which are complete, why it
// closed, so the bag itself tells whether the run was whole (scripts/bag_check.py).
//
// Nothing on a topic is trusted because of its name: a message whose type is not the topic's
// (railvib's topics have theirs; another topic takes its first message's) is not recorded, nor a
// metrics, snapshot or transform message that breaks the message contract
// (railvib/common/message_contract.hpp: a NaN, a sensor the scenario does not have, a grid its
// values do not fill, a rotation that is not one). Each refusal is logged with the publisher and
// counted in the recording status ("refused"), so a foreign publisher cannot put into the bag what
// the reports would plot.
#pragma once

#include <ros/ros.h>
#include <rosbag/bag.h>
#include <topic_tools/shape_shifter.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "railvib/common/sample_stream.hpp"
#include "railvib/common/stream_contract.hpp"

namespace railvib::ros_io {

class BagRecorder {
 public:
  /// Parameters (private): ~bag_path (must not exist), ~streams (list), ~topics (list,
  /// header-stamped), ~tf_topics (list of tf2_msgs/TFMessage topics), ~compression (lz4|none),
  /// ~linger_s, ~min_free_mb (default 2), ~sensor_topics (default false: also record every configured
  /// virtual sensor's sensors/<name>/{imu,velocity,metrics}; ~use_building false leaves out the house
  /// sensors). With /railvib/config_file set, the scenario record (names::kScenarioTopic) is written
  /// first into the bag and published latched.
  BagRecorder(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  ~BagRecorder();

  /// Close the bag once every stream is complete and ~linger_s (default 1 s wall) has passed.
  void poll();
  bool finished() const { return finished_; }
  bool failed() const { return failed_; }
  /// Every expected stream delivered its end_of_stream block.
  bool complete() const;
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
    std::string datatype;  ///< the topic's message type (railvib's, or its first message's)
    std::string md5sum;    ///< and its MD5 sum ("" until known)
    uint64_t refused = 0;  ///< messages not recorded (wrong type, contract broken)
    std::string first_refusal;
    std::vector<std::string> refused_publishers;
  };
  void onMessage(const std::string& topic, const ros::MessageEvent<topic_tools::ShapeShifter const>& event);
  /// Why a non-stream message may not be recorded ("" if it may): its type, then its contract.
  std::string refusal(TopicState& state, const std::string& topic, const topic_tools::ShapeShifter& msg,
                      std::vector<uint8_t>& bytes) const;
  void refuse(TopicState& state, const std::string& topic, const std::string& publisher, const std::string& why);
  bool roomToWrite(size_t next_bytes) const;
  std::string describeSpace() const;
  std::vector<std::string> incompleteStreams() const;
  void writeRecordingStatus(const std::string& status);

  rosbag::Bag bag_;
  std::string bag_path_;
  bool open_ = false;
  bool finished_ = false;
  bool failed_ = false;
  bool all_streams_complete_ = false;
  ros::WallTime all_streams_complete_at_;
  double linger_s_ = 1.0;
  double min_free_mb_ = 2.0;
  std::string space_path_;
  std::vector<std::string> expected_streams_;
  uint64_t message_count_ = 0;
  ros::Time latest_stamp_;
  std::map<std::string, TopicState> topics_;
  StreamLimits limits_;                    ///< the scenario's `limits` (the defaults without a scenario)
  std::vector<std::string> sensor_names_;  ///< the scenario's virtual sensors (metrics must name one)
  std::vector<ros::Subscriber> subscribers_;
  ros::Publisher status_publisher_, diagnostics_publisher_, scenario_publisher_;
};

}  // namespace railvib::ros_io
