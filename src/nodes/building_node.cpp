// building_node: soil footprint velocities in, house response out (see railvib/ros/building_node.hpp).
#include "railvib/ros/building_node.hpp"
#include "railvib/ros/node_config.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "building");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("building", [&] {
    railvib::ros_io::BuildingNode node(nh, private_nh);
    ros::spin();
    if (node.failed()) throw std::runtime_error("stopped on error");
  });
}
