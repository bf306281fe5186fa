// bag_replay_node: replays a recorded railvib bag as live streams (see railvib/ros/bag_replay.hpp).
#include "railvib/ros/bag_replay.hpp"
#include "railvib/ros/node_config.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "bag_replay");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("bag_replay", [&] {
    railvib::ros_io::BagReplay replay(nh, private_nh);
    replay.run();
    ros::spin();  // stay up: latched layouts and queued blocks stay available until the launch ends
  });
}
