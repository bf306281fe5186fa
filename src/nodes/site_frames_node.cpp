// site_frames_node: static tf frames of the site from the scenario config:
// track -> building, track -> one frame per ground sensor (railvib/common/site.hpp),
// building -> building/<response point> and one frame per house sensor.
#include <geometry_msgs/TransformStamped.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "railvib/building/params.hpp"
#include "railvib/common/site.hpp"
#include "railvib/signal/virtual_sensor.hpp"
#include "railvib/ros/node_config.hpp"

namespace {
geometry_msgs::TransformStamped translation(const std::string& child, double x, double y, double z,
                                            const std::string& parent = "track") {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = x;
  t.transform.translation.y = y;
  t.transform.translation.z = z;
  t.transform.rotation.w = 1.0;
  return t;
}
}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "site_frames");
  ros::NodeHandle nh;
  return railvib::ros_io::runNode("site_frames", [&] {
    const railvib::Config config = railvib::ros_io::loadNodeConfig(nh);
    const railvib::SiteLayout site = railvib::loadSiteLayout(config);
    const railvib::building::BuildingParams building = railvib::building::loadBuildingParams(config.root());
    const auto sensors = railvib::signal::loadVirtualSensorConfig(config.root());
    std::vector<geometry_msgs::TransformStamped> frames{
        translation("building", site.building_origin_x_m, site.building_origin_y_m, 0.0)};
    for (const auto& s : site.ground_sensors) frames.push_back(translation("sensor_" + s.name, s.x_m, s.y_m, s.z_m));
    for (const auto& p : building.response_points) {
      frames.push_back(translation("building/" + p.name, p.x_m, p.y_m, p.z_m, "building"));
      for (const auto& s : sensors.sensors) {
        if (s.source == "building" && s.point == p.name) {
          frames.push_back(translation("sensor_" + s.spec.name, p.x_m, p.y_m, p.z_m, "building"));
        }
      }
    }
    tf2_ros::StaticTransformBroadcaster broadcaster;
    broadcaster.sendTransform(frames);
    ros::spin();
  });
}
