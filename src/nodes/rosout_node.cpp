// rosout_node: the log aggregator of a railvib launch (launch/core/roscore.xml), in place of
// Debian's rosout, whose XML-RPC server binds every interface whatever ROS_IP says. It does what
// rosout does for the graph: every node's log messages (/rosout) republished on /rosout_agg, and
// written to rosout.log in the run's log directory.
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <cstdlib>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  ros::init(argc, argv, "rosout", ros::init_options::NoRosout);
  ros::NodeHandle nh;
  ros::Publisher aggregate = nh.advertise<rosgraph_msgs::Log>("/rosout_agg", 0);
  std::ofstream log;
  if (const char* dir = std::getenv("ROS_LOG_DIR")) log.open(std::string(dir) + "/rosout.log", std::ios::app);
  boost::function<void(const rosgraph_msgs::Log::ConstPtr&)> relay = [&](const rosgraph_msgs::Log::ConstPtr& m) {
    aggregate.publish(*m);
    if (log) log << m->header.stamp << " " << m->name << " [" << m->file << ":" << m->line << "] " << m->msg << "\n";
  };
  ros::Subscriber logs = nh.subscribe<rosgraph_msgs::Log>("/rosout", 0, relay);
  ros::spin();
  return 0;
}
