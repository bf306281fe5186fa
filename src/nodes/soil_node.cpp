// soil_node: SoilLoads in, SurfaceVelocities and surface snapshots out (see railvib/ros/soil_node.hpp).
// Under mpirun (haren.launch soil_ranks:=N) rank 0 is the ROS node and the other ranks serve it.
#include "railvib/ros/soil_node.hpp"

#include "railvib/ros/node_config.hpp"
#include "railvib/soil/soil_comm.hpp"

int main(int argc, char** argv) {
  const std::shared_ptr<railvib::soil::SoilComm> comm = railvib::soil::worldSoilComm();
  if (!comm->root()) return railvib::ros_io::SoilNode::serveOtherRank(comm);
  ros::init(argc, argv, "soil");
  ros::NodeHandle nh, private_nh("~");
  const int rc = railvib::ros_io::runNode("soil", [&] {
    railvib::ros_io::SoilNode node(nh, private_nh, comm);
    ros::spin();
    if (node.failed()) throw std::runtime_error("stopped on error");
  });
  // The other ranks may wait inside a collective call: stop them all with the reason.
  if (rc != 0 && comm->size() > 1) comm->abort("soil node (rank 0) stopped on error", rc);
  return rc;
}
