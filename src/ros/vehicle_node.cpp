#include "railvib/ros/vehicle_node.hpp"

#include <geometry_msgs/TransformStamped.h>

#include <cmath>

#include "railvib/common/config.hpp"
#include "railvib/common/names.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/ros/tram_display.hpp"
#include "railvib/ros/wheel_rails.hpp"
#include "railvib/track/track_model.hpp"

namespace railvib::ros_io {

VehicleNode::VehicleNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  int block_samples = 1000;
  int required_subscribers = 1;
  double tf_period_s = 0.01;
  private_nh.param("block_samples", block_samples, block_samples);
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  private_nh.param("tf_period_s", tf_period_s, tf_period_s);
  int tf_required_subscribers = 0;
  private_nh.param("tf_required_subscribers", tf_required_subscribers, tf_required_subscribers);
  // A tf2_ros::TransformBroadcaster would drop the first poses before the recorder connects.
  tf_publisher_ = BlockPublisher<tf2_msgs::TFMessage>(nh, names::kTfTopic, tf_required_subscribers);
  block_samples_ = static_cast<size_t>(std::max(1, block_samples));

  model_ = std::make_unique<vehicle::VehicleModel>(vehicle::loadVehicleParams(config.root()));
  const vehicle::PassageParams passage_params = vehicle::loadPassageParams(config.root());
  const track::TrackParams track_params = track::loadTrackParams(config.root());
  unevenness_ = std::make_unique<vehicle::Unevenness>(vehicle::loadUnevennessParams(config.root()),
                                                      track_params.layout.x_min_m, track_params.layout.x_max_m);
  const bool rigid = passage_params.vehicle_track == vehicle::VehicleTrack::Rigid;
  vehicle::PassageOptions options;
  options.record_poses = true;
  passage_ = std::make_unique<vehicle::VehiclePassage>(*model_, *unevenness_, passage_params,
                                                       vehicle::makeRailSupport(passage_params, track_params), options);
  tf_every_ = std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(tf_period_s / passage_params.time_step_s)));
  publisher_ = BlockPublisher<railvib::ContactForces>(nh, names::kContactForcesTopic, required_subscribers);
  status_ = std::make_unique<NodeStatus>(nh, "vehicle", passage_params.duration_s);
  wheel_rail_ = wheelRailCodes(model_->wheelRails());
  ROS_INFO("vehicle: %d wheels on %s (%s), dt %.3g s, %lu samples", model_->wheelCount(),
           model_->fullWidth() ? "both rails" : "one rail, the half vehicle", rigid ? "rigid" : "flexible",
           passage_params.time_step_s, static_cast<unsigned long>(passage_->totalSamples()));
}

void VehicleNode::run() {
  vehicle::PassageBlock block;
  const double dt = passage_->params().time_step_s;
  while (!passage_->finished() && ros::ok()) {
    const size_t n = passage_->advance(block_samples_, block);
    railvib::ContactForces msg;
    msg.header.frame_id = names::kTrackFrame;
    msg.header.stamp = ros::Time(static_cast<double>(block.first_index) * dt);
    msg.first_sample_index = block.first_index;
    msg.end_of_stream = passage_->finished();
    msg.sample_period_s = dt;
    msg.sample_count = static_cast<uint32_t>(n);
    msg.wheel_count = static_cast<uint32_t>(block.wheel_count);
    msg.wheel_rail = wheel_rail_;
    msg.position_m = block.wheel_x_m;
    msg.force_n = block.contact_force_n;
    msg.unevenness_m = block.unevenness_m;
    publisher_.publish(msg);
    publishPoses(block);
    status_->countSamples("contact_forces out", n);
    status_->update(passage_->time(), passage_->finished());
  }
  status_->finish(passage_->time());
}

void VehicleNode::publishPoses(const vehicle::PassageBlock& block) {
  const auto& bodies = model_->bodies();
  const double radius = model_->wheels().front().radius_m;
  tf2_msgs::TFMessage poses;
  auto& transforms = poses.transforms;
  for (size_t k = 0; k < block.sampleCount(); ++k) {
    const uint64_t index = block.first_index + k;
    if (index % tf_every_ != 0) continue;
    const double t = block.time_s[k];
    const double front_x = passage_->frontAxlePosition(t);
    for (int b = 0; b < block.body_count; ++b) {
      const vehicle::BodyPose& pose = block.poses[k * static_cast<size_t>(block.body_count) + static_cast<size_t>(b)];
      geometry_msgs::TransformStamped tf;
      tf.header.stamp = ros::Time(t);
      tf.header.frame_id = names::kTrackFrame;
      tf.child_frame_id = names::tramBodyFrame(bodies[static_cast<size_t>(b)].name);
      tf.transform.translation.x = front_x - pose.offset_m;
      // Full width: a body of one side sits at its lateral position (the half vehicle's frames stay on
      // the centre line, where the scene draws both of its wheels).
      tf.transform.translation.y = model_->fullWidth() ? pose.lateral_m : 0.0;
      tf.transform.translation.z =
          tramDisplayHeight(bodies[static_cast<size_t>(b)].kind, radius) - pose.vertical_displacement_m;
      // Nose-up pitch is a negative rotation about +y (x forward, z up), left-side-down roll a negative
      // rotation about +x: the quaternion of roll -phi, then pitch -theta (yaw 0).
      const double cr = std::cos(-0.5 * pose.roll_rad), sr = std::sin(-0.5 * pose.roll_rad);
      const double cp = std::cos(-0.5 * pose.pitch_rad), sp = std::sin(-0.5 * pose.pitch_rad);
      tf.transform.rotation.x = sr * cp;
      tf.transform.rotation.y = cr * sp;
      tf.transform.rotation.z = -sr * sp;
      tf.transform.rotation.w = cr * cp;
      transforms.push_back(tf);
    }
  }
  if (!transforms.empty()) tf_publisher_.publish(poses);
}

}  // namespace railvib::ros_io
