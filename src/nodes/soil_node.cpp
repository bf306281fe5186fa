// soil_node: SoilLoads in, SurfaceVelocities and surface snapshots out (see railvib/ros/soil_node.hpp).
#include "railvib/ros/node_config.hpp"
#include "railvib/ros/soil_node.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "soil");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("soil", [&] {
    railvib::ros_io::SoilNode node(nh, private_nh);
    ros::spin();
    if (node.failed()) throw std::runtime_error("stopped on error");
  });
}
