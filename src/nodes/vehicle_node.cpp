// vehicle_node: the coupled T2000 passage; ContactForces and tram tf out (see railvib/ros/vehicle_node.hpp).
#include "railvib/ros/node_config.hpp"
#include "railvib/ros/vehicle_node.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "vehicle");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("vehicle", [&] {
    railvib::ros_io::VehicleNode node(nh, private_nh);
    node.run();
    ros::spin();  // stay up so queued blocks reach slow subscribers; the launch ends the run
  });
}
