// railvib ROS layer: RViz scene of a scenario, live or from a replayed bag.
//
// Publishes
//   visualization/site  (visualization_msgs/MarkerArray, latched): rails and
//       sleepers (from the latched SleeperLayout), the house outline (frame
//       `building`), the sensors with their names (frames sensor_<name>) and
//       the tram bodies, frame-locked to the tf frames tram/<body> so they
//       move with the vehicle poses;
//   visualization/surface_velocity  (sensor_msgs/PointCloud2): each
//       SurfaceSnapshot as one point per soil surface node, field
//       `vertical_velocity_mm_s` for RViz's intensity colouring, and a relief
//       z = ~relief_m_per_mm_s x velocity so the wave is also seen in 3D.
// Nothing here is physics: it only redraws what the streams carry.
#pragma once

#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include "railvib/SleeperLayout.h"
#include "railvib/SurfaceSnapshot.h"
#include "railvib/common/config.hpp"
#include "railvib/common/stream_contract.hpp"

namespace railvib::ros_io {

class SceneVisualizer {
 public:
  /// Private parameters: ~relief_m_per_mm_s (default 0.1).
  SceneVisualizer(ros::NodeHandle& nh, ros::NodeHandle& private_nh);

  /// The site markers from the scenario config: house, sensors, tram (not the track).
  static visualization_msgs::MarkerArray siteMarkers(const Config& config);
  /// Rails and sleepers of a layout (frame `track`).
  static visualization_msgs::MarkerArray trackMarkers(const railvib::SleeperLayout& layout, double rail_gauge_m);

 private:
  void onLayout(const railvib::SleeperLayout::ConstPtr& layout);
  void onSnapshot(const railvib::SurfaceSnapshot::ConstPtr& snapshot);
  void publishSite();

  visualization_msgs::MarkerArray site_markers_;
  double rail_gauge_m_ = 1.435;
  StreamLimits limits_;             ///< the scenario's `limits` (snapshot values are checked against them)
  uint64_t refused_snapshots_ = 0;  ///< snapshots that broke the message contract, not drawn
  double relief_m_per_mm_s_ = 0.1;
  railvib::SleeperLayout::ConstPtr layout_;
  ros::Subscriber layout_subscriber_, snapshot_subscriber_;
  ros::Publisher site_publisher_, cloud_publisher_;
};

}  // namespace railvib::ros_io
