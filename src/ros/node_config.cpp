#include "railvib/ros/node_config.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <unistd.h>

#include <ctime>
#include <sstream>

#include "railvib/common/names.hpp"
#include "railvib/common/version.hpp"
#include "railvib/io/scenario_record.hpp"
#include "railvib/ros/node_status.hpp"
#include "railvib/scenario/launch_arguments.hpp"
#include "railvib/scenario/scenario.hpp"

namespace railvib::ros_io {

Config loadNodeConfig(ros::NodeHandle& nh) {
  std::string file;
  if (!nh.getParam("/railvib/config_file", file)) {
    throw ConfigError("parameter /railvib/config_file is not set (the launch file sets it)");
  }
  std::vector<std::pair<std::string, std::string>> arguments;
  XmlRpc::XmlRpcValue args;
  if (nh.getParam("/railvib/launch_arguments", args)) {
    if (args.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
      throw ConfigError("parameter /railvib/launch_arguments must be a map of argument name -> value");
    }
    for (auto it = args.begin(); it != args.end(); ++it) {
      XmlRpc::XmlRpcValue& v = it->second;
      std::string value;
      switch (v.getType()) {
        case XmlRpc::XmlRpcValue::TypeString:
          value = static_cast<std::string>(v);
          break;
        case XmlRpc::XmlRpcValue::TypeInt:
          value = std::to_string(static_cast<int>(v));
          break;
        case XmlRpc::XmlRpcValue::TypeDouble: {
          std::ostringstream s;
          s.precision(17);
          s << static_cast<double>(v);
          value = s.str();
          break;
        }
        default:
          throw ConfigError("launch argument " + it->first + ": must be one plain value");
      }
      arguments.emplace_back(it->first, value);
    }
  }
  std::vector<std::string> overrides = scenario::launchArgumentOverrides(arguments);
  // A list of "key.path=value" set directly (never built by substitution in our launch files).
  std::vector<std::string> direct;
  nh.getParam("/railvib/config_overrides", direct);
  for (const auto& o : direct) {
    if (!o.empty() && o.back() != '=') overrides.push_back(o);
  }
  Config config = Config::load(file, overrides);
  scenario::validateScenario(config);
  return config;
}

std::string scenarioRecordYaml(ros::NodeHandle& nh, const Config& config) {
  std::string command_line, config_file;
  nh.param<std::string>("/railvib/command_line", command_line, "");
  if (command_line.empty()) command_line = "(not recorded: the launch file did not set /railvib/command_line)";
  nh.getParam("/railvib/config_file", config_file);
  std::map<std::string, std::string> arguments;
  nh.getParam("/railvib/launch_arguments", arguments);
  std::vector<std::string> direct;
  nh.getParam("/railvib/config_overrides", direct);
  char host[256] = {0};
  if (::gethostname(host, sizeof(host) - 1) != 0) host[0] = 0;
  char utc[32] = {0};
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::strftime(utc, sizeof(utc), "%Y-%m-%dT%H:%M:%SZ", &tm);

  io::ScenarioRecordFields fields;
  fields.railvib_version = railvibVersion();
  fields.command_line = command_line;
  fields.config_file = config_file;
  fields.launch_arguments.assign(arguments.begin(), arguments.end());
  fields.config_overrides = direct;
  fields.host = host;
  fields.recorded_utc = utc;
  return io::scenarioRecordYaml(fields, config);
}

void reportStartFailure(const std::string& node, const std::string& message) {
  ROS_FATAL("%s: %s", node.c_str(), message.c_str());
  // After NodeStatus::fail the ERROR is out and ROS is shut down: a NodeHandle would restart it.
  if (!ros::isInitialized() || !ros::ok() || !ros::master::check()) return;
  // Latched, so a subscriber that connects in the next moment still gets it.
  ros::NodeHandle nh;
  ros::Publisher publisher = nh.advertise<diagnostic_msgs::DiagnosticArray>(names::kDiagnosticsTopic, 1, true);
  diagnostic_msgs::DiagnosticArray array;
  diagnostic_msgs::DiagnosticStatus status;
  status.name = "railvib/" + node;
  status.hardware_id = node;
  status.level = diagnostic_msgs::DiagnosticStatus::ERROR;
  status.message = message;
  array.status.push_back(status);
  publisher.publish(array);
  // A subscriber still connecting gets the latched ERROR once connected (up to kDiagnosticsConnectWaitS).
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(kDiagnosticsConnectWaitS);
  while (publisher.getNumSubscribers() == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  ros::WallDuration(0.5).sleep();
}

}  // namespace railvib::ros_io
