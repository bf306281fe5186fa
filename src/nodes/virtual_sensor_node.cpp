// virtual_sensor_node: soil / building velocities in, virtual accelerometer
// samples, metrics and diagnostics out (see railvib/ros/virtual_sensor_node.hpp).
#include "railvib/ros/virtual_sensor_node.hpp"

#include "railvib/ros/node_config.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "virtual_sensor");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("virtual_sensor", [&] {
    railvib::ros_io::VirtualSensorNode node(nh, private_nh);
    ros::spin();
    if (node.failed()) throw std::runtime_error("stopped on error");
  });
}
