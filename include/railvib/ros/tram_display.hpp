// railvib ROS layer: how the tram is drawn (RViz only, no physics).
//
// The vehicle model is planar (vertical displacement and pitch of each body,
// relative to the unloaded reference). The tf frames tram/<body> place each
// body's reference point at a display height above the rail head, and the
// visualizer draws boxes and wheels around those frames. The carbody boxes
// span each carbody's extent (`extent_m` in the vehicle file).
#pragma once

#include <string>
#include <vector>

#include "railvib/vehicle/vehicle_model.hpp"

namespace railvib::ros_io {

/// Height of the rail head above the soil surface in frame `track` (m): ballast and sleeper, display only.
constexpr double kRailHeadDisplayZM = 0.65;

/// Height of a body's tf frame above the soil surface in frame `track` (m), at rest.
double tramDisplayHeight(vehicle::BodyKind kind, double wheel_radius_m);

// Outline of the T2000 for display [public]: 2.30 m wide, floor 0.35 m, roof 3.3 m above the rail.
constexpr double kTramWidthM = 2.30;
constexpr double kTramCarbodyHeightM = 2.95;
constexpr double kBogieHeightM = 0.35;

}  // namespace railvib::ros_io
