// moving_load_node: constant moving axle loads as ContactForces (track scenario).
#include "railvib/ros/moving_load_source.hpp"
#include "railvib/ros/node_config.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "moving_load");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("moving_load", [&] {
    railvib::ros_io::MovingLoadSourceNode node(nh, private_nh);
    node.run();
    ros::spin();  // stay up so queued blocks reach slow subscribers; the launch ends the run
  });
}
