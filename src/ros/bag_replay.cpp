#include "railvib/ros/bag_replay.hpp"

#include <rosbag/view.h>
#include <rosgraph_msgs/Clock.h>
#include <topic_tools/shape_shifter.h>

#include <stdexcept>

#include "railvib/common/names.hpp"

namespace railvib::ros_io {

BagReplay::BagReplay(ros::NodeHandle& nh, ros::NodeHandle& private_nh) : nh_(nh) {
  if (!private_nh.getParam("bag", bag_path_)) throw std::runtime_error("~bag (the bag to replay) is not set");
  private_nh.param("rate", rate_, rate_);
  private_nh.param("loop", loop_, loop_);
  private_nh.param("publish_clock", publish_clock_, publish_clock_);
  private_nh.param("required_subscribers", required_subscribers_, required_subscribers_);
  private_nh.param("start_delay_s", start_delay_s_, start_delay_s_);
  if (!(start_delay_s_ >= 0.0)) throw std::runtime_error("~start_delay_s must be >= 0");
  private_nh.getParam("topics", topics_);
  if (!(rate_ > 0.0)) throw std::runtime_error("~rate must be > 0");
  try {
    bag_.open(bag_path_, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("cannot read bag " + bag_path_ + ": " + e.what() +
                             " (truncated or corrupt? `rosbag reindex` can repair an unclosed bag)");
  }
  // Validate the whole bag once before publishing anything: a corrupt chunk fails here, not mid-replay.
  try {
    rosbag::View view(bag_);
    size_t n = 0;
    for (const rosbag::MessageInstance& m : view) {
      (void)m.size();
      ++n;
    }
    if (n == 0) throw std::runtime_error("bag " + bag_path_ + " holds no message");
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("bag " + bag_path_ + " is unreadable: " + e.what());
  }
  if (publish_clock_) clock_publisher_ = nh_.advertise<rosgraph_msgs::Clock>(names::kClockTopic, 100);
}

void BagReplay::run() {
  bool first = true;
  do {
    playOnce(first);
    first = false;
  } while (loop_ && ros::ok());
}

void BagReplay::playOnce(bool first_pass) {
  std::unique_ptr<rosbag::View> view = topics_.empty()
                                           ? std::make_unique<rosbag::View>(bag_)
                                           : std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topics_));
  if (view->size() == 0) throw std::runtime_error("none of the requested topics is in " + bag_path_);
  if (first_pass) {
    for (const rosbag::ConnectionInfo* c : view->getConnections()) {
      if (publishers_.count(c->topic)) continue;
      const bool latched = c->datatype == "railvib/PointLayout" || c->datatype == "railvib/SleeperLayout";
      ros::AdvertiseOptions opts(c->topic, 0, c->md5sum, c->datatype, c->msg_def);
      opts.latch = latched;
      publishers_[c->topic] = nh_.advertise(opts);
    }
    // Wait for the consumers of the first data topic (e.g. the virtual sensor node).
    for (auto& [topic, pub] : publishers_) {
      (void)topic;
      const ros::WallTime start = ros::WallTime::now();
      while (ros::ok() && static_cast<int>(pub.getNumSubscribers()) < required_subscribers_ &&
             (ros::WallTime::now() - start).toSec() < 30.0) {
        ros::WallDuration(0.01).sleep();
      }
      break;
    }
    if (start_delay_s_ > 0.0) ros::WallDuration(start_delay_s_).sleep();
  }
  const ros::Time bag_start = view->getBeginTime();
  const ros::WallTime wall_start = ros::WallTime::now();
  for (const rosbag::MessageInstance& m : *view) {
    if (!ros::ok()) return;
    const double due_s = (m.getTime() - bag_start).toSec() / rate_;
    const double wait_s = due_s - (ros::WallTime::now() - wall_start).toSec();
    if (wait_s > 0.0) ros::WallDuration(wait_s).sleep();
    if (publish_clock_) {
      rosgraph_msgs::Clock clock;
      clock.clock = m.getTime();
      clock_publisher_.publish(clock);
    }
    auto shape = m.instantiate<topic_tools::ShapeShifter>();
    publishers_.at(m.getTopic()).publish(*shape);
  }
}

}  // namespace railvib::ros_io
