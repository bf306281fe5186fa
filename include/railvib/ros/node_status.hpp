// railvib ROS layer: per-node status on /diagnostics (about once per wall
// second): progress, simulated time, real-time factor, ETA and the rate of
// every stream the node consumes or produces (samples per wall second).
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>

#include <map>
#include <string>

#include "railvib/common/progress.hpp"

namespace railvib::ros_io {

/// How long a node that fails waits for a subscriber of /diagnostics to connect before it exits, so
/// the latched ERROR reaches it: a monitor or test that is still connecting on a loaded machine
/// (2 s was short when two test suites ran at once).
inline constexpr double kDiagnosticsConnectWaitS = 5.0;

class NodeStatus {
 public:
  NodeStatus(ros::NodeHandle& nh, std::string node_name, double total_sim_s);

  /// Count samples of a stream (in or out).
  void countSamples(const std::string& stream, uint64_t samples) { streams_[stream].samples += samples; }
  /// Report progress at simulated time t (prints the console line and publishes diagnostics when due).
  void update(double sim_time_s, bool force = false);
  void finish(double sim_time_s);
  /// Mark an error (published as ERROR with the message).
  void error(const std::string& message);
  /// The node cannot go on: FATAL log line naming the node, ERROR on /diagnostics, ROS shutdown
  /// (a required node's exit then stops the launch).
  void fail(const std::string& message);
  bool failed() const { return failed_; }
  /// Run one message's work unless the node has failed; an exception fails the node.
  template <class Body>
  void guard(Body&& body) {
    if (failed_) return;
    try {
      body();
    } catch (const std::exception& e) {
      fail(e.what());
    }
  }

 private:
  void publish(double sim_time_s, uint8_t level, const std::string& message);
  struct StreamCount {
    uint64_t samples = 0;
    uint64_t samples_at_last = 0;
  };
  std::string name_;
  ProgressReporter progress_;
  ros::Publisher publisher_;
  std::map<std::string, StreamCount> streams_;
  ros::WallTime last_publish_;
  bool failed_ = false;
};

}  // namespace railvib::ros_io
