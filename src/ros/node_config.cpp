#include "railvib/ros/node_config.hpp"

namespace railvib::ros_io {

Config loadNodeConfig(ros::NodeHandle& nh) {
  std::string file;
  if (!nh.getParam("/railvib/config_file", file)) {
    throw ConfigError("parameter /railvib/config_file is not set (the launch file sets it)");
  }
  std::vector<std::string> overrides;
  nh.getParam("/railvib/config_overrides", overrides);
  std::vector<std::string> effective;
  for (const auto& o : overrides) {
    // Launch files pass "key=" for arguments left empty: those keep the config value.
    if (!o.empty() && o.back() != '=') effective.push_back(o);
  }
  return Config::load(file, effective);
}

}  // namespace railvib::ros_io
