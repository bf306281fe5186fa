// railvib/vehicle: linear multibody model of a vehicle described as data
// (vehicle_params.hpp), half vehicle on one rail.
//
// Planar vertical model (bounce + pitch). Vertical displacements are positive
// DOWNWARD (track convention), pitch is positive nose-up (rear end down):
// the downward displacement of a point of a body at offset s behind the front
// axle is w(s) = z + (s - s_c) * theta, s_c the body's reference point (its
// centre of mass).
//
// Full coordinates, in the order of the bodies in the file: z (and theta for
// carbodies and bogies) of every body; the T2000 (A1)+Bo'+(1A) has 22.
// Elements: each suspension is a spring-damper between the same point of its
// two bodies, e = w_upper(x) - w_lower(x), K += k e e^T; a vertical pin joint
// adds its relative-pitch spring/damper and the holonomic constraint "both
// bodies move alike at the pin", which is eliminated exactly: full = T *
// reduced, the second body's bounce being expressed by the others' (the
// T2000's two pins: 20 reduced DOF). A body or element on the centre line
// counts with body_share_per_rail, one of a side once (vehicle_params.hpp).
// Wheels: the contact DOF is the bounce of the wheel's body.
//
// The model is linear; gravity is a constant load; the Hertz contact is in
// the passage solver (passage.hpp). All springs are unstressed at q = 0.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::vehicle {

/// A rigid body of the model (for poses and mode names).
struct BodyInfo {
  std::string name;  ///< e.g. "front_carbody", "leading_bogie", "axle0_tread"
  BodyKind kind = BodyKind::Carbody;
  int index = 0;                ///< carbodies and bogies: index among their kind; wheel parts: the wheel (axle) index
  double offset_m = 0.0;        ///< reference point behind the front axle
  Eigen::Index z_dof = -1;      ///< full-coordinate index of z
  Eigen::Index theta_dof = -1;  ///< full-coordinate index of theta (-1: no pitch)
  double front_m = 0.0;         ///< longitudinal extent behind the front axle
  double rear_m = 0.0;
  /// Wheel parts: the bogie they hang from (index in bodies(), -1: none); bogies: themselves.
  int bogie = -1;
  /// Bogies: half the span of their wheels (m).
  double half_wheelbase_m = 0.0;
};

struct WheelInfo {
  int axle = 0;
  AxleType type = AxleType::Motor;
  double offset_m = 0.0;  ///< behind the front axle
  double radius_m = 0.34;
  /// Mass of the body that carries the contact (tread or trailer wheel), kg.
  double contact_mass_kg = 0.0;
  int bogie = 0;                  ///< index of its bogie among the bogies (-1: none)
  int body = -1;                  ///< index of the contact body in bodies()
  Eigen::Index contact_dof = -1;  ///< reduced-coordinate DOF carrying the contact (tread / trailer wheel)
};

/// Pose of a body (per sample, for the node's tf): downward displacement and nose-up pitch.
struct BodyPose {
  double offset_m = 0.0;                 ///< reference point behind the front axle
  double vertical_displacement_m = 0.0;  ///< positive downward (from the unloaded reference)
  double pitch_rad = 0.0;                ///< positive nose-up
};

class VehicleModel {
 public:
  /// Throws std::invalid_argument for a vehicle that is a mechanism (a motion of its bodies that
  /// stretches no element while the wheels stand on the rail); loadVehicleParams checks this.
  explicit VehicleModel(const VehicleParams& params);

  const VehicleParams& params() const { return params_; }
  /// Reduced (independent) coordinates.
  Eigen::Index dofCount() const { return M_.rows(); }
  Eigen::Index fullDofCount() const { return T_.rows(); }
  const Eigen::MatrixXd& mass() const { return M_; }
  const Eigen::MatrixXd& damping() const { return C_; }
  const Eigen::MatrixXd& stiffness() const { return K_; }
  /// Gravity load (N, downward) in reduced coordinates.
  const Eigen::VectorXd& gravityLoad() const { return fg_; }
  /// full = T * reduced.
  const Eigen::MatrixXd& transform() const { return T_; }
  /// Diagonal mass of the full coordinates (kg or kg m^2).
  const Eigen::VectorXd& fullMassDiagonal() const { return m_full_; }
  const std::vector<std::string>& fullDofNames() const { return full_names_; }

  int wheelCount() const { return static_cast<int>(wheels_.size()); }
  const std::vector<WheelInfo>& wheels() const { return wheels_; }
  const std::vector<BodyInfo>& bodies() const { return bodies_; }
  /// Contact selection: column i = unit vector on wheel i's contact DOF (n x nw).
  const Eigen::MatrixXd& contactSelection() const { return B_; }

  /// Total mass per rail (kg) and weight per rail (N).
  double totalMassPerRail() const { return total_mass_; }
  double weightPerRail() const { return total_mass_ * params_.gravity_m_s2; }

  /// Poses of all bodies for a reduced displacement vector.
  std::vector<BodyPose> poses(const Eigen::VectorXd& q) const;
  /// Display name of a bogie or the bogie of a wheel part ("leading bogie"), or "vehicle".
  std::string bogieLabel(const BodyInfo& body) const;

 private:
  VehicleParams params_;
  Eigen::MatrixXd M_, C_, K_, T_, B_;
  Eigen::VectorXd fg_, m_full_;
  std::vector<std::string> full_names_;
  std::vector<WheelInfo> wheels_;
  std::vector<BodyInfo> bodies_;
  double total_mass_ = 0.0;
};

/// The weight per rail shared equally by the wheels (N): the constant moving loads that stand for
/// the vehicle in track-only runs (`railvib_tool moving-load`, the track scenario).
std::vector<double> uniformStaticWheelLoadsPerRail(const VehicleModel& model);

}  // namespace railvib::vehicle
