#include "railvib/ros/track_node.hpp"

#include <cmath>

#include "railvib/SleeperLayout.h"
#include "railvib/common/names.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::ros_io {

TrackNode::TrackNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  const track::TrackParams params = track::loadTrackParams(config.root());
  // The same `simulation` section as the vehicle (step, duration, speed, start), validated once.
  const vehicle::PassageParams run = vehicle::loadPassageParams(config.root());
  const double rate_hz = params.load_sample_rate_hz;
  // A convected start must match the vehicle's, or the ballast loads differ from the coupled run.
  stream_ = std::make_unique<track::SoilLoadStream>(params, run.time_step_s, rate_hz,
                                                    run.convected_track_start ? run.speed_m_s : 0.0);
  status_ = std::make_unique<NodeStatus>(nh, "track", run.duration_s);

  double block_duration_s = 0.05;
  int required_subscribers = 1;
  private_nh.param("block_duration_s", block_duration_s, block_duration_s);
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  block_samples_ = std::max<size_t>(1, static_cast<size_t>(std::lround(block_duration_s * rate_hz)));

  layout_publisher_ = nh.advertise<railvib::SleeperLayout>(names::kSleeperLayoutTopic, 1, true);
  railvib::SleeperLayout layout;
  layout.header.frame_id = names::kTrackFrame;
  layout.position_m = stream_->sleeperPositions();
  layout.length_m = params.layout.length_m;
  layout.width_m = params.layout.width_m;
  layout_publisher_.publish(layout);

  loads_publisher_ = BlockPublisher<railvib::SoilLoads>(nh, names::kSoilLoadsTopic, required_subscribers);
  contact_subscriber_ = nh.subscribe(names::kContactForcesTopic, 0, &TrackNode::onContactForces, this);
  ROS_INFO("track: %d sleepers, dt %.3g s, soil loads at %.0f Hz in blocks of %zu samples, start %s",
           stream_->sleeperCount(), run.time_step_s, rate_hz, block_samples_,
           run.convected_track_start ? "convected with the loads" : "at rest");
}

void TrackNode::onContactForces(const railvib::ContactForces::ConstPtr& msg) {
  if (!ended_) status_->guard([&] { consume(*msg); });
}

void TrackNode::consume(const railvib::ContactForces& block) {
  const railvib::ContactForces* msg = &block;
  tracker_.accept(msg->first_sample_index, msg->sample_count);
  if (std::abs(msg->sample_period_s - stream_->timeStep()) > 1e-12 * stream_->timeStep()) {
    throw std::runtime_error("contact forces come every " + std::to_string(msg->sample_period_s) +
                             " s but the track steps every " + std::to_string(stream_->timeStep()) +
                             " s (simulation.time_step_s)");
  }
  const size_t expected = static_cast<size_t>(msg->sample_count) * msg->wheel_count;
  if (msg->position_m.size() != expected || msg->force_n.size() != expected) {
    throw std::runtime_error("malformed ContactForces block: array sizes do not match sample_count x wheel_count");
  }
  stream_->push(msg->sample_count, msg->wheel_count, msg->position_m.data(), msg->force_n.data(), pending_);
  if (msg->end_of_stream) {
    stream_->flush(pending_);
    ended_ = true;
  }
  publishPending(ended_);
  status_->countSamples("contact_forces in", msg->sample_count);
  status_->update(stream_->time(), ended_);
  if (ended_) status_->finish(stream_->time());
}

void TrackNode::publishPending(bool end_of_stream) {
  const size_t sleepers = static_cast<size_t>(stream_->sleeperCount());
  const size_t consumed = splitIntoBlocks(
      pending_.size() / sleepers, block_samples_, end_of_stream, [&](size_t offset, size_t count, bool last) {
        railvib::SoilLoads block;
        block.header.frame_id = names::kTrackFrame;
        block.header.stamp = ros::Time(static_cast<double>(next_load_index_) * stream_->loadSamplePeriod());
        block.first_sample_index = next_load_index_;
        block.end_of_stream = last;
        block.sample_period_s = stream_->loadSamplePeriod();
        block.sample_count = static_cast<uint32_t>(count);
        block.sleeper_count = static_cast<uint32_t>(sleepers);
        block.force_n.assign(pending_.begin() + static_cast<long>(offset * sleepers),
                             pending_.begin() + static_cast<long>((offset + count) * sleepers));
        loads_publisher_.publish(block);
        status_->countSamples("soil_loads out", count);
        next_load_index_ += count;
      });
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<long>(consumed * sleepers));
}

}  // namespace railvib::ros_io
