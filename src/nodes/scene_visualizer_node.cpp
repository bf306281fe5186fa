// scene_visualizer_node: RViz markers of the site and tram, and the soil surface
// velocity as a point cloud (see railvib/ros/scene_visualizer.hpp).
#include "railvib/ros/node_config.hpp"
#include "railvib/ros/scene_visualizer.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "scene_visualizer");
  ros::NodeHandle nh, private_nh("~");
  return railvib::ros_io::runNode("scene_visualizer", [&] {
    railvib::ros_io::SceneVisualizer visualizer(nh, private_nh);
    ros::spin();
  });
}
