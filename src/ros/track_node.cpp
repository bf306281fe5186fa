#include "railvib/ros/track_node.hpp"

#include <cmath>

#include "railvib/SleeperLayout.h"
#include "railvib/common/names.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/ros/wheel_rails.hpp"
#include "railvib/vehicle/vehicle_model.hpp"
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
  limits_ = loadStreamLimits(config.root());
  // The wheels the vehicle streams and the rail under each (a wheel per rail per axle at full width).
  wheel_rails_ = vehicle::VehicleModel(vehicle::loadVehicleParams(config.root())).wheelRails();
  wheel_rail_codes_ = wheelRailCodes(wheel_rails_);
  wheel_count_ = static_cast<uint32_t>(wheel_rails_.size());

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
  layout.rail_seat_y_m = track::soilRailSeatPositions(params);
  layout_publisher_.publish(layout);

  loads_publisher_ = BlockPublisher<railvib::SoilLoads>(nh, names::kSoilLoadsTopic, required_subscribers);
  contact_subscriber_ = nh.subscribe(names::kContactForcesTopic, 0, &TrackNode::onContactForces, this);
  ROS_INFO(
      "track: %d sleepers, %s, dt %.3g s, soil loads at %.0f Hz in blocks of %zu samples, start %s",
      stream_->sleeperCount(),
      stream_->soilLoadsPerSleeper() == 1 ? "half track (the soil gets both rails)" : "both rails, a load per seat",
      run.time_step_s, rate_hz, block_samples_, run.convected_track_start ? "convected with the loads" : "at rest");
}

void TrackNode::onContactForces(const railvib::ContactForces::ConstPtr& msg) {
  status_->guard([&] {
    if (ended_) {
      throw StreamContractError("stream " + contact_subscriber_.getTopic() + ": a block (first_sample_index " +
                                std::to_string(msg->first_sample_index) + ") after the end_of_stream block");
    }
    consume(*msg);
  });
}

void TrackNode::consume(const railvib::ContactForces& block) {
  const railvib::ContactForces* msg = &block;
  // Period, wheel count, array sizes and values against the config, before any of them is used.
  BlockContract contract;
  contract.stream = contact_subscriber_.getTopic();
  contract.sample_period_s = stream_->timeStep();
  contract.period_source = "simulation.time_step_s = " + formatValue(stream_->timeStep()) + " s";
  contract.count_field = "wheel_count";
  contract.point_label = "wheel";
  contract.point_count = wheel_count_;
  contract.point_source = "the vehicle (vehicles.<name>.wheels, one per rail at track.width = full)";
  contract.max_block_samples = limits_.max_block_samples;
  validateBlock(
      contract,
      {msg->first_sample_index, msg->end_of_stream != 0, msg->sample_period_s, msg->sample_count, msg->wheel_count},
      {{"position_m", &msg->position_m, 1, limits_.wheel_position_m, "limits.wheel_position_m", "m"},
       {"force_n", &msg->force_n, 1, limits_.contact_force_n, "limits.contact_force_n", "N"},
       {"unevenness_m", &msg->unevenness_m, 1, limits_.unevenness_m, "limits.unevenness_m", "m"}});
  validatePointCodes(contract, "wheel_rail", msg->wheel_rail, wheel_rail_codes_,
                     "the vehicle (its wheels in order, 0 = left rail, 1 = right)");
  tracker_.accept(msg->first_sample_index, msg->sample_count);
  stream_->push(msg->sample_count, wheel_rails_, msg->position_m.data(), msg->force_n.data(), pending_);
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
  const size_t frame = stream_->soilLoadsPerFrame();  // sleepers x seats_per_sleeper
  const size_t consumed = splitIntoBlocks(
      pending_.size() / frame, block_samples_, end_of_stream, [&](size_t offset, size_t count, bool last) {
        railvib::SoilLoads block;
        block.header.frame_id = names::kTrackFrame;
        block.header.stamp = ros::Time(static_cast<double>(next_load_index_) * stream_->loadSamplePeriod());
        block.first_sample_index = next_load_index_;
        block.end_of_stream = last;
        block.sample_period_s = stream_->loadSamplePeriod();
        block.sample_count = static_cast<uint32_t>(count);
        block.sleeper_count = static_cast<uint32_t>(sleepers);
        block.seats_per_sleeper = static_cast<uint32_t>(stream_->soilLoadsPerSleeper());
        block.force_n.assign(pending_.begin() + static_cast<long>(offset * frame),
                             pending_.begin() + static_cast<long>((offset + count) * frame));
        loads_publisher_.publish(block);
        status_->countSamples("soil_loads out", count);
        next_load_index_ += count;
      });
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<long>(consumed * frame));
}

}  // namespace railvib::ros_io
