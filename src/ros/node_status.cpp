#include "railvib/ros/node_status.hpp"

#include "railvib/common/names.hpp"

namespace railvib::ros_io {

NodeStatus::NodeStatus(ros::NodeHandle& nh, std::string node_name, double total_sim_s)
    : name_(std::move(node_name)),
      progress_(name_, total_sim_s),
      // Latched: the last status (an ERROR when the node stopped) reaches a late subscriber too.
      publisher_(nh.advertise<diagnostic_msgs::DiagnosticArray>(names::kDiagnosticsTopic, 10, true)),
      last_publish_(ros::WallTime::now()) {}

void NodeStatus::update(double sim_time_s, bool force) {
  progress_.update(sim_time_s, force);
  if (force || (ros::WallTime::now() - last_publish_).toSec() >= 1.0) {
    publish(sim_time_s, diagnostic_msgs::DiagnosticStatus::OK, progress_.line(sim_time_s));
  }
}

void NodeStatus::finish(double sim_time_s) {
  progress_.finish(sim_time_s);
  publish(sim_time_s, diagnostic_msgs::DiagnosticStatus::OK, "finished");
}

void NodeStatus::error(const std::string& message) { publish(0.0, diagnostic_msgs::DiagnosticStatus::ERROR, message); }

void NodeStatus::fail(const std::string& message) {
  if (failed_) return;
  failed_ = true;
  ROS_FATAL("%s: %s", name_.c_str(), message.c_str());
  error(message);
  // Let the ERROR leave before the connections close: a subscriber to /diagnostics that is still
  // connecting to this node (a refusal at start-up) gets the latched ERROR once it is connected.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(kDiagnosticsConnectWaitS);
  while (publisher_.getNumSubscribers() == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  ros::WallDuration(0.5).sleep();
  ros::shutdown();
}

void NodeStatus::publish(double sim_time_s, uint8_t level, const std::string& message) {
  const ros::WallTime now = ros::WallTime::now();
  const double wall_dt = std::max(1e-9, (now - last_publish_).toSec());
  last_publish_ = now;
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time(sim_time_s);
  diagnostic_msgs::DiagnosticStatus status;
  status.name = "railvib/" + name_;
  status.hardware_id = name_;
  status.level = level;
  status.message = message;
  auto kv = [&](const std::string& key, const std::string& value) {
    diagnostic_msgs::KeyValue p;
    p.key = key;
    p.value = value;
    status.values.push_back(p);
  };
  kv("simulated time [s]", std::to_string(sim_time_s));
  kv("real-time factor", std::to_string(progress_.realTimeFactor(sim_time_s)));
  for (auto& [stream, count] : streams_) {
    kv(stream + " samples", std::to_string(count.samples));
    kv(stream + " rate [samples/s wall]",
       std::to_string(static_cast<double>(count.samples - count.samples_at_last) / wall_dt));
    count.samples_at_last = count.samples;
  }
  array.status.push_back(status);
  publisher_.publish(array);
}

}  // namespace railvib::ros_io
