// site_frames_node: static tf frames of the site from the scenario config:
// track -> building (railvib/common/site.hpp), building -> building/<response point>,
// and one frame per virtual sensor, named after the sensor (names::sensorFrame): a soil sensor at
// its ground sensor (frame track), a house sensor at its response point (frame building).
#include <geometry_msgs/TransformStamped.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "railvib/building/params.hpp"
#include "railvib/common/names.hpp"
#include "railvib/common/site.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/signal/virtual_sensor.hpp"

namespace {
namespace names = railvib::names;

geometry_msgs::TransformStamped translation(const std::string& child, const railvib::NamedPoint& at,
                                            const std::string& parent) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = at.x_m;
  t.transform.translation.y = at.y_m;
  t.transform.translation.z = at.z_m;
  t.transform.rotation.w = 1.0;
  return t;
}

const railvib::NamedPoint* find(const std::vector<railvib::NamedPoint>& points, const std::string& name) {
  for (const auto& p : points) {
    if (p.name == name) return &p;
  }
  return nullptr;
}
}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "site_frames");
  ros::NodeHandle nh;
  return railvib::ros_io::runNode("site_frames", [&] {
    const railvib::Config config = railvib::ros_io::loadNodeConfig(nh);
    const railvib::SiteLayout site = railvib::loadSiteLayout(config.root());
    const railvib::building::BuildingParams building = railvib::building::loadBuildingParams(config.root());
    const auto sensors = railvib::signal::loadVirtualSensorConfig(config.root());
    std::vector<geometry_msgs::TransformStamped> frames{
        translation(names::kBuildingFrame, {"", building.placement.origin_x_m, building.placement.origin_y_m, 0.0, ""},
                    names::kTrackFrame)};
    for (const auto& p : building.response_points) {
      frames.push_back(translation(names::buildingPointFrame(p.name), p, names::kBuildingFrame));
    }
    for (const auto& s : sensors.sensors) {
      const bool in_house = s.source == "building";
      const railvib::NamedPoint* at = find(in_house ? building.response_points : site.ground_sensors, s.point);
      // A soil sensor at another receiver (e.g. on the receiver line) has no site frame.
      if (at) {
        frames.push_back(
            translation(names::sensorFrame(s.spec.name), *at, in_house ? names::kBuildingFrame : names::kTrackFrame));
      }
    }
    tf2_ros::StaticTransformBroadcaster broadcaster;
    broadcaster.sendTransform(frames);
    ros::spin();
  });
}
