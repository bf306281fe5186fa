// track_node: ContactForces in, SoilLoads out (see railvib/ros/track_node.hpp).
#include "railvib/ros/track_node.hpp"

#include "railvib/ros/node_config.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "track");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("track", [&] {
    railvib::ros_io::TrackNode node(nh, private_nh);
    ros::spin();
    if (node.failed()) throw std::runtime_error("stopped on error");
  });
}
