// bag_recorder_node: records the railvib streams into one bag at simulation
// time and exits when every stream is complete (see railvib/ros/bag_recorder.hpp).
#include <ros/ros.h>

#include "railvib/ros/bag_recorder.hpp"
#include "railvib/ros/node_config.hpp"

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
    // Non-zero unless every stream is in the bag, whole: an interrupted run is a failed run.
    return recorder.failed() || !recorder.complete() ? 1 : 0;
  } catch (const std::exception& e) {
    railvib::ros_io::reportStartFailure("recorder", e.what());
    return 1;
  }
}
