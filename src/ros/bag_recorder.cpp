#include "railvib/ros/bag_recorder.hpp"

#include <std_msgs/Header.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <boost/bind/bind.hpp>
#include <filesystem>

namespace railvib::ros_io {

namespace {
struct StreamPrefix {
  std_msgs::Header header;
  uint64_t first_sample_index = 0;
  bool end_of_stream = false;
  double sample_period_s = 0.0;
  uint32_t sample_count = 0;
};

std::vector<uint8_t> serializedBytes(const topic_tools::ShapeShifter& msg) {
  std::vector<uint8_t> buffer(msg.size());
  ros::serialization::OStream out(buffer.data(), static_cast<uint32_t>(buffer.size()));
  msg.write(out);
  return buffer;
}

// All railvib stream messages begin with the same fields (see msg/*.msg).
StreamPrefix readStreamPrefix(std::vector<uint8_t>& bytes) {
  StreamPrefix p;
  ros::serialization::IStream in(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, p.header);
  uint8_t eos = 0;
  in.next(p.first_sample_index);
  in.next(eos);
  in.next(p.sample_period_s);
  in.next(p.sample_count);
  p.end_of_stream = eos != 0;
  return p;
}

// A TFMessage has no header of its own: its time is that of its newest transform.
ros::Time latestTransformStamp(std::vector<uint8_t>& bytes) {
  tf2_msgs::TFMessage tf;
  ros::serialization::IStream in(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, tf);
  ros::Time latest;
  for (const auto& t : tf.transforms) latest = std::max(latest, t.header.stamp);
  return latest;
}

std_msgs::Header readHeader(std::vector<uint8_t>& bytes) {
  std_msgs::Header h;
  ros::serialization::IStream in(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, h);
  return h;
}
}  // namespace

BagRecorder::BagRecorder(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  std::vector<std::string> streams, topics, tf_topics;
  private_nh.getParam("streams", streams);
  private_nh.getParam("topics", topics);
  private_nh.getParam("tf_topics", tf_topics);
  private_nh.param<std::string>("bag_path", bag_path_, "railvib.bag");
  std::string compression;
  private_nh.param<std::string>("compression", compression, "lz4");
  private_nh.param("linger_s", linger_s_, linger_s_);
  if (streams.empty() && topics.empty()) throw std::runtime_error("bag_recorder: no ~streams or ~topics to record");

  const auto parent = std::filesystem::path(bag_path_).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  bag_.open(bag_path_, rosbag::bagmode::Write);
  bag_.setCompression(compression == "none" ? rosbag::compression::Uncompressed : rosbag::compression::LZ4);
  open_ = true;

  status_publisher_ = private_nh.advertise<std_msgs::String>("status", 1, true);
  enum class Kind { Stream, Stamped, Tf };
  auto subscribe = [&](const std::string& name, Kind kind) {
    const std::string resolved = nh.resolveName(name);
    TopicState& state = topics_[resolved];
    const bool is_stream = kind == Kind::Stream;
    state.is_stream = is_stream;
    state.is_tf = kind == Kind::Tf;
    if (is_stream) state.tracker = std::make_unique<SampleIndexTracker>(resolved);
    boost::function<void(const ros::MessageEvent<topic_tools::ShapeShifter const>&)> cb =
        [this, resolved](const ros::MessageEvent<topic_tools::ShapeShifter const>& e) { onMessage(resolved, e); };
    subscribers_.push_back(nh.subscribe<topic_tools::ShapeShifter>(resolved, 0, cb));
  };
  for (const auto& s : streams) subscribe(s, Kind::Stream);
  for (const auto& t : topics) subscribe(t, Kind::Stamped);
  for (const auto& t : tf_topics) subscribe(t, Kind::Tf);
  ROS_INFO("bag_recorder: recording %zu stream(s), %zu topic(s) and %zu tf topic(s) to %s", streams.size(),
           topics.size(), tf_topics.size(), bag_path_.c_str());
}

BagRecorder::~BagRecorder() { close("shutdown"); }

void BagRecorder::onMessage(const std::string& topic, const ros::MessageEvent<topic_tools::ShapeShifter const>& event) {
  if (!open_) return;
  const auto msg = event.getConstMessage();
  TopicState& state = topics_.at(topic);
  if (state.is_stream && state.ended) {
    ROS_WARN("bag_recorder: %s: message after end_of_stream ignored", topic.c_str());
    return;
  }
  std::vector<uint8_t> bytes = serializedBytes(*msg);
  ros::Time stamp;
  bool ends_stream = false;
  try {
    if (state.is_stream) {
      const StreamPrefix p = readStreamPrefix(bytes);
      state.tracker->accept(p.first_sample_index, p.sample_count);
      stamp = p.header.stamp;
      ends_stream = p.end_of_stream;
    } else if (state.is_tf) {
      stamp = latestTransformStamp(bytes);
    } else {
      stamp = readHeader(bytes).stamp;
    }
  } catch (const StreamGapError& e) {
    ROS_FATAL("bag_recorder: %s", e.what());
    failed_ = true;
    close(std::string("stream gap: ") + e.what());
    return;
  } catch (const ros::Exception& e) {
    ROS_FATAL("bag_recorder: %s: message does not start like a railvib stream block: %s", topic.c_str(), e.what());
    failed_ = true;
    close("malformed message on " + topic);
    return;
  }
  // Bag times must be >= TIME_MIN; simulation time starts at 0.
  if (stamp < ros::TIME_MIN) stamp = ros::TIME_MIN;
  bag_.write(topic, stamp, *msg, event.getConnectionHeaderPtr());
  if (state.messages == 0) state.first_stamp = stamp;
  state.last_stamp = stamp;
  ++state.messages;
  if (ends_stream) {
    state.ended = true;
    bool all_ended = true;
    for (const auto& kv : topics_) all_ended = all_ended && (!kv.second.is_stream || kv.second.ended);
    if (all_ended) {
      // Messages on other topics published just before the last end_of_stream
      // (e.g. final metrics) may still be in flight: keep recording a little.
      all_streams_complete_at_ = ros::WallTime::now();
      all_streams_complete_ = true;
    }
  }
}

void BagRecorder::poll() {
  if (all_streams_complete_ && !finished_ && (ros::WallTime::now() - all_streams_complete_at_).toSec() >= linger_s_) {
    finished_ = true;
    close("all streams complete");
  }
}

void BagRecorder::close(const std::string& reason) {
  if (!open_) return;
  bag_.close();
  open_ = false;
  for (const auto& [name, state] : topics_) {
    ROS_INFO("bag_recorder: %-32s %8lu messages%s", name.c_str(), static_cast<unsigned long>(state.messages),
             state.is_stream ? (state.ended ? "  (stream complete)" : "  (stream NOT complete)") : "");
  }
  ROS_INFO("bag_recorder: closed %s (%s)", bag_path_.c_str(), reason.c_str());
  std_msgs::String status;
  status.data = failed_ ? "failed: " + reason : "closed: " + reason;
  status_publisher_.publish(status);
}

}  // namespace railvib::ros_io
