#include "railvib/ros/scene_visualizer.hpp"

#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>

#include "railvib/building/params.hpp"
#include "railvib/common/message_contract.hpp"
#include "railvib/common/names.hpp"
#include "railvib/common/site.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/ros/tram_display.hpp"
#include "railvib/signal/virtual_sensor.hpp"
#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::ros_io {

namespace {
using visualization_msgs::Marker;

std_msgs::ColorRGBA colour(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

geometry_msgs::Point point(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

Marker marker(const std::string& frame, const std::string& ns, int id, int type) {
  Marker m;
  m.header.frame_id = frame;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  return m;
}

Marker box(const std::string& frame, const std::string& ns, int id, double cx, double cy, double cz, double lx,
           double ly, double lz, const std_msgs::ColorRGBA& c) {
  Marker m = marker(frame, ns, id, Marker::CUBE);
  m.pose.position = point(cx, cy, cz);
  m.scale.x = lx;
  m.scale.y = ly;
  m.scale.z = lz;
  m.color = c;
  return m;
}

// The 12 edges of an axis-aligned box as LINE_LIST points.
void addBoxEdges(Marker& lines, double x0, double y0, double z0, double x1, double y1, double z1) {
  const double xs[2] = {x0, x1}, ys[2] = {y0, y1}, zs[2] = {z0, z1};
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      lines.points.push_back(point(x0, ys[a], zs[b]));
      lines.points.push_back(point(x1, ys[a], zs[b]));
      lines.points.push_back(point(xs[a], y0, zs[b]));
      lines.points.push_back(point(xs[a], y1, zs[b]));
      lines.points.push_back(point(xs[a], ys[b], z0));
      lines.points.push_back(point(xs[a], ys[b], z1));
    }
  }
}

void addSensor(visualization_msgs::MarkerArray& out, const std::string& name, int& id) {
  const std::string frame = names::sensorFrame(name);
  Marker sphere = marker(frame, "sensors", id++, Marker::SPHERE);
  sphere.scale.x = sphere.scale.y = sphere.scale.z = 0.5;
  sphere.color = colour(1.0f, 0.85f, 0.0f);
  out.markers.push_back(sphere);
  Marker label = marker(frame, "sensor_labels", id++, Marker::TEXT_VIEW_FACING);
  label.pose.position.z = 1.0;
  label.scale.z = 0.6;
  label.color = colour(1.0f, 1.0f, 1.0f);
  label.text = name;
  out.markers.push_back(label);
}
}  // namespace

SceneVisualizer::SceneVisualizer(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  rail_gauge_m_ = loadSiteLayout(config.root()).rail_gauge_m;
  limits_ = loadStreamLimits(config.root());
  site_markers_ = siteMarkers(config);
  private_nh.param("relief_m_per_mm_s", relief_m_per_mm_s_, relief_m_per_mm_s_);
  site_publisher_ = nh.advertise<visualization_msgs::MarkerArray>(names::kSiteMarkersTopic, 1, true);
  cloud_publisher_ = nh.advertise<sensor_msgs::PointCloud2>(names::kSurfaceCloudTopic, 10);
  publishSite();
  layout_subscriber_ = nh.subscribe(names::kSleeperLayoutTopic, 1, &SceneVisualizer::onLayout, this);
  snapshot_subscriber_ = nh.subscribe(names::kSurfaceSnapshotTopic, 10, &SceneVisualizer::onSnapshot, this);
}

visualization_msgs::MarkerArray SceneVisualizer::siteMarkers(const Config& config) {
  visualization_msgs::MarkerArray out;
  const SiteLayout site = loadSiteLayout(config.root());
  int id = 0;

  // The house: one translucent volume and the edges of each storey (frame `building`).
  if (config.root().has("building")) {
    const building::BuildingParams house = building::loadBuildingParams(config.root());
    out.markers.push_back(box(names::kBuildingFrame, "building", id++, 0.5 * house.length_m, 0.5 * house.width_m,
                              0.5 * house.height_m, house.length_m, house.width_m, house.height_m,
                              colour(0.85f, 0.75f, 0.6f, 0.25f)));
    Marker edges = marker(names::kBuildingFrame, "building_edges", id++, Marker::LINE_LIST);
    edges.scale.x = 0.06;
    edges.color = colour(0.95f, 0.9f, 0.8f);
    const double storey_height_m = house.height_m / house.storeys;
    for (int s = 0; s < house.storeys; ++s) {
      addBoxEdges(edges, 0.0, 0.0, s * storey_height_m, house.length_m, house.width_m, (s + 1) * storey_height_m);
    }
    out.markers.push_back(edges);
    out.markers.push_back(box(names::kBuildingFrame, "building_foundation", id++, 0.5 * house.length_m,
                              0.5 * house.width_m, -0.5 * house.foundation_depth_m, house.length_m, house.width_m,
                              house.foundation_depth_m, colour(0.5f, 0.5f, 0.5f, 0.35f)));
  }

  // Sensors: every virtual sensor, in its frame (site_frames_node).
  if (config.root().has("virtual_sensors")) {
    for (const auto& s : signal::loadVirtualSensorConfig(config.root()).sensors) addSensor(out, s.spec.name, id);
  }

  // The tram, frame-locked to tram/<body> so each body follows its tf pose.
  if (config.root().has("vehicle")) {
    const vehicle::VehicleModel model(vehicle::loadVehicleParams(config.root()));
    const double half_gauge_m = 0.5 * site.rail_gauge_m;
    for (const vehicle::BodyInfo& body : model.bodies()) {
      const std::string frame = names::tramBodyFrame(body.name);
      std::vector<Marker> parts;
      switch (body.kind) {
        case vehicle::BodyKind::Carbody: {
          // Offsets are behind the front axle; frame x points forward.
          const double centre_x = body.offset_m - 0.5 * (body.front_m + body.rear_m);
          parts.push_back(box(frame, "tram_carbodies", id++, centre_x, 0.0, 0.0, body.rear_m - body.front_m - 0.1,
                              kTramWidthM, kTramCarbodyHeightM, colour(0.35f, 0.65f, 0.95f, 0.7f)));
          break;
        }
        case vehicle::BodyKind::Bogie:
          parts.push_back(box(frame, "tram_bogies", id++, body.offset_m - 0.5 * (body.front_m + body.rear_m), 0.0, 0.0,
                              body.rear_m - body.front_m, site.rail_gauge_m + 0.3, kBogieHeightM,
                              colour(0.3f, 0.3f, 0.3f)));
          break;
        case vehicle::BodyKind::Tread:
        case vehicle::BodyKind::Wheel: {
          const double radius_m = model.wheels().at(static_cast<size_t>(body.index)).radius_m;
          // The body of one side at full width (its frame at its rail) has one wheel; a half vehicle's
          // or a centre-line wheelset's frame is on the centre line, with a wheel on each rail.
          const bool one_side = model.fullWidth() && body.y_m != 0.0;
          for (const double y :
               one_side ? std::vector<double>{0.0} : std::vector<double>{-half_gauge_m, half_gauge_m}) {
            Marker wheel = marker(frame, "tram_wheels", id++, Marker::CYLINDER);
            wheel.pose.position.y = y;
            // Cylinder axis (z) turned onto y.
            wheel.pose.orientation.x = std::sqrt(0.5);
            wheel.pose.orientation.w = std::sqrt(0.5);
            wheel.scale.x = wheel.scale.y = 2.0 * radius_m;
            wheel.scale.z = 0.12;
            wheel.color = colour(0.1f, 0.1f, 0.1f);
            parts.push_back(wheel);
          }
          break;
        }
        case vehicle::BodyKind::WheelHub:
          break;  // inside the wheel: drawn by its tread
      }
      for (Marker& m : parts) {
        m.frame_locked = true;
        out.markers.push_back(m);
      }
    }
  }
  return out;
}

visualization_msgs::MarkerArray SceneVisualizer::trackMarkers(const railvib::SleeperLayout& layout,
                                                              double rail_gauge_m) {
  visualization_msgs::MarkerArray out;
  if (layout.position_m.empty()) return out;
  const auto [min_it, max_it] = std::minmax_element(layout.position_m.begin(), layout.position_m.end());
  const double x0 = *min_it - 0.3, x1 = *max_it + 0.3;
  constexpr double kRailHeightM = 0.15, kSleeperDepthM = 0.2;
  int id = 0;
  for (const double y : {-0.5 * rail_gauge_m, 0.5 * rail_gauge_m}) {
    out.markers.push_back(box(names::kTrackFrame, "rails", id++, 0.5 * (x0 + x1), y,
                              kRailHeadDisplayZM - 0.5 * kRailHeightM, x1 - x0, 0.07, kRailHeightM,
                              colour(0.75f, 0.75f, 0.8f)));
  }
  Marker sleepers = marker(names::kTrackFrame, "sleepers", id++, Marker::CUBE_LIST);
  sleepers.scale.x = layout.width_m;
  sleepers.scale.y = layout.length_m;
  sleepers.scale.z = kSleeperDepthM;
  sleepers.color = colour(0.55f, 0.5f, 0.45f);
  for (const double x : layout.position_m) {
    sleepers.points.push_back(point(x, 0.0, kRailHeadDisplayZM - kRailHeightM - 0.5 * kSleeperDepthM));
  }
  out.markers.push_back(sleepers);
  return out;
}

void SceneVisualizer::publishSite() {
  visualization_msgs::MarkerArray all = site_markers_;
  if (layout_) {
    for (const auto& m : trackMarkers(*layout_, rail_gauge_m_).markers) all.markers.push_back(m);
  }
  site_publisher_.publish(all);
}

void SceneVisualizer::onLayout(const railvib::SleeperLayout::ConstPtr& layout) {
  layout_ = layout;
  publishSite();
}

void SceneVisualizer::onSnapshot(const railvib::SurfaceSnapshot::ConstPtr& snapshot) {
  // A snapshot stands alone (anyone may publish one): checked before a point of it is drawn.
  try {
    validateSurfaceSnapshot(names::kSurfaceSnapshotTopic, snapshot->origin_x_m, snapshot->origin_y_m,
                            snapshot->spacing_x_m, snapshot->spacing_y_m, snapshot->nx, snapshot->ny,
                            snapshot->vertical_velocity_m_s, limits_,
                            {&snapshot->velocity_x_m_s, &snapshot->velocity_y_m_s});
  } catch (const StreamContractError& e) {
    ++refused_snapshots_;
    ROS_WARN_THROTTLE(5.0, "scene_visualizer: snapshot %lu skipped (%lu refused so far): %s",
                      static_cast<unsigned long>(snapshot->sample_index),
                      static_cast<unsigned long>(refused_snapshots_), e.what());
    return;
  }
  sensor_msgs::PointCloud2 cloud;
  cloud.header = snapshot->header;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2Fields(4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                                "z", 1, sensor_msgs::PointField::FLOAT32, "vertical_velocity_mm_s", 1,
                                sensor_msgs::PointField::FLOAT32);
  modifier.resize(static_cast<size_t>(snapshot->nx) * snapshot->ny);
  cloud.height = snapshot->ny;
  cloud.width = snapshot->nx;
  cloud.row_step = cloud.width * cloud.point_step;
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z"),
      v(cloud, "vertical_velocity_mm_s");
  for (uint32_t iy = 0; iy < snapshot->ny; ++iy) {
    for (uint32_t ix = 0; ix < snapshot->nx; ++ix, ++x, ++y, ++z, ++v) {
      const float v_mm_s = 1000.0f * snapshot->vertical_velocity_m_s[iy * snapshot->nx + ix];
      *x = static_cast<float>(snapshot->origin_x_m + ix * snapshot->spacing_x_m);
      *y = static_cast<float>(snapshot->origin_y_m + iy * snapshot->spacing_y_m);
      *z = static_cast<float>(relief_m_per_mm_s_) * v_mm_s;
      *v = v_mm_s;
    }
  }
  cloud_publisher_.publish(cloud);
}

}  // namespace railvib::ros_io
