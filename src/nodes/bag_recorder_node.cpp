// bag_recorder_node: records the railvib streams into one bag at simulation
// time and exits when every stream is complete (see railvib/ros/bag_recorder.hpp).
#include <ros/ros.h>

#include "railvib/ros/bag_recorder.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "bag_recorder");
  ros::NodeHandle nh, private_nh("~");
  try {
    railvib::ros_io::BagRecorder recorder(nh, private_nh);
    while (ros::ok() && !recorder.finished() && !recorder.failed()) {
      ros::spinOnce();
      recorder.poll();
      ros::WallDuration(0.001).sleep();
    }
    recorder.close(ros::ok() ? "finished" : "interrupted");
    ros::WallDuration(0.2).sleep();  // let the latched status go out
    return recorder.failed() ? 1 : 0;
  } catch (const std::exception& e) {
    ROS_FATAL("bag_recorder: %s", e.what());
    return 1;
  }
}
