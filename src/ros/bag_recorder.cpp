#include "railvib/ros/bag_recorder.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/Vector3Stamped.h>
#include <railvib/BuildingResponse.h>
#include <railvib/ContactForces.h>
#include <railvib/PointLayout.h>
#include <railvib/SectionSnapshot.h>
#include <railvib/SensorSamples.h>
#include <railvib/SleeperLayout.h>
#include <railvib/SoilLoads.h>
#include <railvib/SurfaceSnapshot.h>
#include <railvib/SurfaceVelocities.h>
#include <railvib/VibrationMetrics.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Header.h>
#include <std_msgs/String.h>
#include <sys/statvfs.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <boost/bind/bind.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "railvib/common/message_contract.hpp"
#include "railvib/common/names.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/signal/virtual_sensor.hpp"

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

// Bytes free for this process on the file system holding `path` (-1 if unknown).
double freeBytes(const std::string& path) {
  struct statvfs st {};
  if (::statvfs(path.c_str(), &st) != 0) return -1.0;
  return static_cast<double>(st.f_bavail) * static_cast<double>(st.f_frsize);
}

std_msgs::Header readHeader(std::vector<uint8_t>& bytes) {
  std_msgs::Header h;
  ros::serialization::IStream in(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, h);
  return h;
}

template <typename M>
M deserialized(std::vector<uint8_t>& bytes) {
  M m;
  ros::serialization::IStream in(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, m);
  return m;
}

struct MessageType {
  std::string datatype, md5sum;
};
template <typename M>
MessageType typeOf() {
  return {ros::message_traits::DataType<M>::value(), ros::message_traits::MD5Sum<M>::value()};
}

// The message type of each of railvib's topics (resolved names), and of a sensor's own topics.
std::map<std::string, MessageType> railvibTopicTypes(ros::NodeHandle& nh) {
  return {{nh.resolveName(names::kContactForcesTopic), typeOf<railvib::ContactForces>()},
          {nh.resolveName(names::kSoilLoadsTopic), typeOf<railvib::SoilLoads>()},
          {nh.resolveName(names::kSurfaceVelocitiesTopic), typeOf<railvib::SurfaceVelocities>()},
          {nh.resolveName(names::kBuildingResponseTopic), typeOf<railvib::BuildingResponse>()},
          {nh.resolveName(names::kSensorSamplesTopic), typeOf<railvib::SensorSamples>()},
          {nh.resolveName(names::kSleeperLayoutTopic), typeOf<railvib::SleeperLayout>()},
          {nh.resolveName(names::kSurfacePointsTopic), typeOf<railvib::PointLayout>()},
          {nh.resolveName(names::kBuildingPointsTopic), typeOf<railvib::PointLayout>()},
          {nh.resolveName(names::kSurfaceSnapshotTopic), typeOf<railvib::SurfaceSnapshot>()},
          {nh.resolveName(names::kSectionSnapshotTopic), typeOf<railvib::SectionSnapshot>()},
          {nh.resolveName(names::kSensorMetricsTopic), typeOf<railvib::VibrationMetrics>()},
          {names::kTfTopic, typeOf<tf2_msgs::TFMessage>()},
          {"/tf_static", typeOf<tf2_msgs::TFMessage>()}};
}

MessageType sensorTopicType(const std::string& what) {
  if (what == "metrics") return typeOf<railvib::VibrationMetrics>();
  if (what == "imu") return typeOf<sensor_msgs::Imu>();
  if (what == "velocity") return typeOf<geometry_msgs::Vector3Stamped>();
  return {};
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
  private_nh.param("min_free_mb", min_free_mb_, min_free_mb_);
  // The scenario that produces the run (validated like every node's), and its sensors' own topics.
  std::string scenario_yaml;
  std::map<std::string, MessageType> topic_types = railvibTopicTypes(nh);
  if (nh.hasParam("/railvib/config_file")) {
    const Config config = loadNodeConfig(nh);
    scenario_yaml = scenarioRecordYaml(nh, config);
    limits_ = loadStreamLimits(config.root());
    bool sensor_topics = false, use_building = true;
    private_nh.param("sensor_topics", sensor_topics, sensor_topics);
    private_nh.param("use_building", use_building, use_building);
    for (const auto& sensor : signal::loadVirtualSensorConfig(config.root()).sensors) {
      if (sensor.source == "building" && !use_building) continue;
      sensor_names_.push_back(sensor.spec.name);
      for (const char* what : {"imu", "velocity", "metrics"}) {
        const std::string topic = names::sensorTopic(sensor.spec.name, what);
        topic_types[nh.resolveName(topic)] = sensorTopicType(what);
        if (sensor_topics) topics.push_back(topic);
      }
    }
  } else {
    ROS_WARN("bag_recorder: /railvib/config_file is not set: the bag will not record the scenario");
  }
  if (streams.empty() && topics.empty()) throw std::runtime_error("bag_recorder: no ~streams or ~topics to record");
  expected_streams_.clear();
  for (const auto& st : streams) expected_streams_.push_back(nh.resolveName(st));

  status_publisher_ = private_nh.advertise<std_msgs::String>("status", 1, true);
  diagnostics_publisher_ = nh.advertise<diagnostic_msgs::DiagnosticArray>(names::kDiagnosticsTopic, 1, true);
  // Never overwrite a bag: an earlier run's results stay (./railvib run picks a new name for its default).
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::symlink_status(bag_path_, ec))) {
    throw std::runtime_error("bag_recorder: " + bag_path_ +
                             " exists: refusing to overwrite it (move it away, or record to another bag:=FILE)");
  }
  const auto parent = std::filesystem::path(bag_path_).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  space_path_ = parent.empty() ? std::string(".") : parent.string();
  try {
    bag_.open(bag_path_, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("bag_recorder: cannot write " + bag_path_ + ": " + e.what());
  }
  bag_.setCompression(compression == "none" ? rosbag::compression::Uncompressed : rosbag::compression::LZ4);
  open_ = true;
  if (!roomToWrite(0)) {
    failed_ = true;
    close("disk full before the first message");
    throw std::runtime_error("bag_recorder: disk full: " + describeSpace());
  }

  if (!scenario_yaml.empty()) {
    std_msgs::String record;
    record.data = scenario_yaml;
    scenario_publisher_ = nh.advertise<std_msgs::String>(names::kScenarioTopic, 1, true);
    scenario_publisher_.publish(record);
    try {
      bag_.write(names::kScenarioTopic, ros::TIME_MIN, record);
    } catch (const rosbag::BagException& e) {
      failed_ = true;
      close(std::string("write error: ") + e.what());
      throw std::runtime_error("bag_recorder: cannot write " + bag_path_ + ": " + e.what());
    }
  }

  enum class Kind { Stream, Stamped, Tf };
  auto subscribe = [&](const std::string& name, Kind kind) {
    const std::string resolved = nh.resolveName(name);
    TopicState& state = topics_[resolved];
    const bool is_stream = kind == Kind::Stream;
    state.is_stream = is_stream;
    state.is_tf = kind == Kind::Tf;
    if (is_stream) state.tracker = std::make_unique<SampleIndexTracker>(resolved);
    const auto known = topic_types.find(resolved);
    if (known != topic_types.end()) {
      state.datatype = known->second.datatype;
      state.md5sum = known->second.md5sum;
    } else if (state.is_tf) {
      const MessageType tf = typeOf<tf2_msgs::TFMessage>();
      state.datatype = tf.datatype;
      state.md5sum = tf.md5sum;
    }
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
  std::string why_not;
  try {
    why_not = refusal(state, topic, *msg, bytes);
  } catch (const ros::Exception& e) {
    why_not = std::string("its bytes are not a ") + msg->getDataType() + ": " + e.what();
  }
  if (!why_not.empty()) {
    refuse(state, topic, event.getPublisherName(), why_not);
    return;
  }
  ros::Time stamp;
  bool ends_stream = false;
  try {
    if (state.is_stream) {
      const StreamPrefix p = readStreamPrefix(bytes);
      if (!(std::isfinite(p.sample_period_s) && p.sample_period_s > 0.0)) {
        throw StreamGapError("stream '" + topic + "': sample_period_s = " + std::to_string(p.sample_period_s) +
                             " is not a positive period (block at sample " + std::to_string(p.first_sample_index) +
                             ")");
      }
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
    close(std::string("stream error: ") + e.what());
    return;
  } catch (const ros::Exception& e) {
    ROS_FATAL("bag_recorder: %s: message does not start like a railvib stream block: %s", topic.c_str(), e.what());
    failed_ = true;
    close("malformed message on " + topic);
    return;
  }
  // Bag times must be >= TIME_MIN; simulation time starts at 0.
  if (stamp < ros::TIME_MIN) stamp = ros::TIME_MIN;
  // Stop while there is still room to close the bag (last chunk, index): it stays readable.
  if (!roomToWrite(bytes.size())) {
    ROS_FATAL("bag_recorder: disk full: %s; recording stopped before %s", describeSpace().c_str(), topic.c_str());
    failed_ = true;
    close("disk full: " + describeSpace());
    return;
  }
  try {
    bag_.write(topic, stamp, *msg, event.getConnectionHeaderPtr());
  } catch (const rosbag::BagException& e) {
    ROS_FATAL("bag_recorder: writing %s failed: %s (%s)", topic.c_str(), e.what(), describeSpace().c_str());
    failed_ = true;
    close(std::string("write error: ") + e.what() + " (" + describeSpace() + ")");
    return;
  }
  if (stamp > latest_stamp_) latest_stamp_ = stamp;
  if (state.messages == 0) state.first_stamp = stamp;
  state.last_stamp = stamp;
  ++state.messages;
  ++message_count_;
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

std::string BagRecorder::refusal(TopicState& state, const std::string& topic, const topic_tools::ShapeShifter& msg,
                                 std::vector<uint8_t>& bytes) const {
  // A topic carries one type: railvib's for its own topics, else the first message's.
  if (state.datatype.empty()) {
    state.datatype = msg.getDataType();
    state.md5sum = msg.getMD5Sum();
  }
  if (msg.getDataType() != state.datatype || msg.getMD5Sum() != state.md5sum) {
    return "a " + msg.getDataType() + " (MD5 " + msg.getMD5Sum() + ") on a topic of " + state.datatype + " (MD5 " +
           state.md5sum + ")";
  }
  if (state.is_stream) return "";  // the stream contract's checks follow (continuity, period)
  try {
    if (state.datatype == ros::message_traits::DataType<railvib::VibrationMetrics>::value()) {
      const auto m = deserialized<railvib::VibrationMetrics>(bytes);
      MetricsFields f;
      f.sensor_name = m.sensor_name;
      f.kind = m.kind;
      f.resolved_hz = m.resolved_hz;
      f.kb_f = m.kb_f;
      f.kb_f_max = m.kb_f_max;
      f.ppv_m_s = m.ppv_m_s;
      f.ppv_vertical_m_s = m.ppv_vertical_m_s;
      f.governing_component = m.governing_component;
      f.governing_ppv_m_s = m.governing_ppv_m_s;
      f.dominant_frequency_hz = m.dominant_frequency_hz;
      f.din4150_3_limit_m_s = m.din4150_3_limit_m_s;
      f.third_octave_center_hz = &m.third_octave_center_hz;
      f.third_octave_level_db = &m.third_octave_level_db;
      f.din4150_2_verdict = m.din4150_2_verdict;
      f.din4150_2_a_u = m.din4150_2_a_u;
      f.din4150_2_a_o = m.din4150_2_a_o;
      f.din4150_2_a_r = m.din4150_2_a_r;
      f.din4150_3_verdict = m.din4150_3_verdict;
      f.verdict = m.verdict;
      validateMetrics(topic, f, limits_, sensor_names_);
    } else if (state.datatype == ros::message_traits::DataType<railvib::SurfaceSnapshot>::value()) {
      const auto m = deserialized<railvib::SurfaceSnapshot>(bytes);
      validateSurfaceSnapshot(topic, m.origin_x_m, m.origin_y_m, m.spacing_x_m, m.spacing_y_m, m.nx, m.ny,
                              m.vertical_velocity_m_s, limits_, {&m.velocity_x_m_s, &m.velocity_y_m_s});
    } else if (state.datatype == ros::message_traits::DataType<railvib::SectionSnapshot>::value()) {
      const auto m = deserialized<railvib::SectionSnapshot>(bytes);
      validateSectionSnapshot(topic, m.x_m, m.origin_y_m, m.spacing_y_m, m.ny, m.depth_m, m.vertical_velocity_m_s,
                              limits_, {&m.velocity_x_m_s, &m.velocity_y_m_s});
    } else if (state.is_tf) {
      for (const auto& t : deserialized<tf2_msgs::TFMessage>(bytes).transforms) {
        const auto& tr = t.transform.translation;
        const auto& q = t.transform.rotation;
        const double translation[3] = {tr.x, tr.y, tr.z};
        const double rotation[4] = {q.x, q.y, q.z, q.w};
        validateTransform(topic, t.header.frame_id, t.child_frame_id, translation, rotation);
      }
    }
  } catch (const StreamContractError& e) {
    return e.what();
  }
  return "";
}

void BagRecorder::refuse(TopicState& state, const std::string& topic, const std::string& publisher,
                         const std::string& why) {
  ++state.refused;
  if (state.first_refusal.empty()) state.first_refusal = why;
  if (std::find(state.refused_publishers.begin(), state.refused_publishers.end(), publisher) ==
          state.refused_publishers.end() &&
      state.refused_publishers.size() < 16) {
    state.refused_publishers.push_back(publisher);
  }
  // The first ten of each topic and every 100th: a flood of foreign messages does not flood the log.
  if (state.refused <= 10 || state.refused % 100 == 0) {
    ROS_WARN("bag_recorder: %s: not recording a message from %s (%lu refused on this topic): %s", topic.c_str(),
             publisher.c_str(), static_cast<unsigned long>(state.refused), why.c_str());
  }
}

void BagRecorder::poll() {
  if (all_streams_complete_ && !finished_ && (ros::WallTime::now() - all_streams_complete_at_).toSec() >= linger_s_) {
    finished_ = true;
    close("all streams complete");
  }
}

bool BagRecorder::roomToWrite(size_t next_bytes) const {
  const double free = freeBytes(space_path_);
  if (free < 0.0) return true;  // unknown: rely on the write errors
  // The chunk in memory (rosbag flushes it at ~768 KB), its index, the connection and chunk records
  // written at close, and the next message must still fit.
  const double reserve =
      min_free_mb_ * 1e6 + 32.0 * static_cast<double>(message_count_) + static_cast<double>(next_bytes);
  return free >= reserve;
}

std::string BagRecorder::describeSpace() const {
  const double free = freeBytes(space_path_);
  std::ostringstream s;
  s.precision(3);
  s << (free < 0.0 ? std::string("free space unknown")
                   : std::to_string(static_cast<long long>(free / 1e6)) + " MB free")
    << " on the file system of " << space_path_ << ", " << min_free_mb_ << " MB kept to close the bag";
  return s.str();
}

std::vector<std::string> BagRecorder::incompleteStreams() const {
  std::vector<std::string> out;
  for (const auto& name : expected_streams_) {
    const auto it = topics_.find(name);
    if (it == topics_.end() || !it->second.ended) out.push_back(name);
  }
  return out;
}

void BagRecorder::writeRecordingStatus(const std::string& status) {
  nlohmann::json j;
  j["status"] = status;
  j["expected_streams"] = expected_streams_;
  std::vector<std::string> complete;
  for (const auto& name : expected_streams_) {
    const auto it = topics_.find(name);
    if (it != topics_.end() && it->second.ended) complete.push_back(name);
  }
  j["complete_streams"] = complete;
  j["incomplete_streams"] = incompleteStreams();
  nlohmann::json counts = nlohmann::json::object();
  nlohmann::json refused = nlohmann::json::object();
  for (const auto& [name, state] : topics_) {
    counts[name] = state.messages;
    if (state.refused > 0) {
      refused[name] = {
          {"messages", state.refused}, {"first_reason", state.first_refusal}, {"publishers", state.refused_publishers}};
    }
  }
  j["messages"] = counts;
  // Messages kept out of the bag (a wrong type, a broken message contract), per topic.
  j["refused"] = refused;
  std_msgs::String msg;
  msg.data = j.dump();
  bag_.write(names::kRecordingStatusTopic, std::max(latest_stamp_, ros::TIME_MIN), msg);
}

void BagRecorder::close(const std::string& reason) {
  if (!open_) return;
  open_ = false;
  const std::vector<std::string> incomplete = incompleteStreams();
  const std::string status = (failed_ ? "failed: " : "closed: ") + reason;
  bool indexed = true;
  try {
    writeRecordingStatus(status);
  } catch (const rosbag::BagException& e) {
    ROS_ERROR("bag_recorder: could not record the status in the bag: %s", e.what());
  }
  try {
    bag_.close();
  } catch (const rosbag::BagException& e) {
    indexed = false;
    ROS_FATAL("bag_recorder: closing %s failed: %s; the bag is left unindexed (`rosbag reindex` may recover it)",
              bag_path_.c_str(), e.what());
  }
  uint64_t refused = 0;
  for (const auto& [name, state] : topics_) {
    ROS_INFO("bag_recorder: %-32s %8lu messages%s", name.c_str(), static_cast<unsigned long>(state.messages),
             state.is_stream ? (state.ended ? "  (stream complete)" : "  (stream NOT complete)") : "");
    if (state.refused > 0) {
      ROS_WARN("bag_recorder: %-32s %8lu messages refused, not recorded (first: %s)", name.c_str(),
               static_cast<unsigned long>(state.refused), state.first_refusal.c_str());
    }
    refused += state.refused;
  }
  if (!incomplete.empty()) {
    std::string list;
    for (const auto& n : incomplete) list += (list.empty() ? "" : ", ") + n;
    ROS_ERROR("bag_recorder: incomplete streams: %s", list.c_str());
  }
  ROS_INFO("bag_recorder: closed %s (%s)%s", bag_path_.c_str(), reason.c_str(), indexed ? "" : " UNINDEXED");
  std_msgs::String msg;
  msg.data = status;
  status_publisher_.publish(msg);
  // Like every node: its end on /diagnostics, ERROR when the recording failed or is not whole.
  diagnostic_msgs::DiagnosticArray diag;
  diagnostic_msgs::DiagnosticStatus st;
  st.name = "railvib/recorder";
  st.hardware_id = "recorder";
  st.level = failed_ || !incomplete.empty() ? diagnostic_msgs::DiagnosticStatus::ERROR
             : refused > 0                  ? diagnostic_msgs::DiagnosticStatus::WARN
                                            : diagnostic_msgs::DiagnosticStatus::OK;
  st.message =
      status + (refused > 0 ? "; " + std::to_string(refused) + " foreign or malformed message(s) refused" : "");
  diag.status.push_back(st);
  diagnostics_publisher_.publish(diag);
}

bool BagRecorder::complete() const { return incompleteStreams().empty(); }

}  // namespace railvib::ros_io
