// railvib/vehicle: linear multibody model of the T2000, half vehicle on one rail.
//
// Planar vertical model (bounce + pitch). Vertical displacements are positive
// DOWNWARD (track convention), pitch is positive nose-up (rear end down):
// the downward displacement of a point of a body at offset s behind the front
// axle is w(s) = z + (s - s_c) * theta, s_c the body's reference point.
//
// Bodies (full coordinates, 22 DOF for (A1)+Bo'+(1A)):
//   3 carbodies   z, theta (front, central, rear)
//   3 bogies      z, theta (leading, middle, rear)
//   motor wheel   z of the motor-wheel mass (primary k_m, d_m to the bogie)
//                 and z of the tread (resilient ring k_t, d_t to the motor mass;
//                 the tread carries the wheel/rail contact)
//   trailer wheel z (primary k_d, d_d to the bogie; carries the contact)
// Joint model: each articulation is a vertical pin between neighbouring
// carbodies (equal vertical displacement of both bodies at the pin, relative
// pitch free but for an optional pitch spring/damper). The two pin
// constraints are eliminated exactly: full = T * reduced, reduced coordinates
// (z_front, theta_front, theta_central, theta_rear, bogies, wheels), 20 DOF.
// Each carbody rests on its bogie through the secondary suspension (one
// element per bogie side at the bogie centre); the end carbodies also hang on
// their articulation with the central carbody, which sits on the middle bogie.
//
// The model is linear; gravity is a constant load; the Hertz contact is in
// the passage solver (passage.hpp). All springs are unstressed at q = 0.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::vehicle {

enum class BodyKind { Carbody, Bogie, MotorWheel, Tread, TrailerWheel };

/// A rigid body of the model (for poses and mode names).
struct BodyInfo {
  std::string name;  ///< e.g. "front_carbody", "leading_bogie", "axle0_tread"
  BodyKind kind = BodyKind::Carbody;
  int index = 0;                ///< carbody/bogie index 0..2, or axle index
  double offset_m = 0.0;        ///< reference point behind the front axle
  Eigen::Index z_dof = -1;      ///< full-coordinate index of z
  Eigen::Index theta_dof = -1;  ///< full-coordinate index of theta (-1: no pitch)
};

struct WheelInfo {
  int axle = 0;
  AxleType type = AxleType::Motor;
  double offset_m = 0.0;  ///< behind the front axle
  double radius_m = 0.34;
  /// Mass of the body that carries the contact (tread or trailer wheel), kg.
  double contact_mass_kg = 0.0;
  int bogie = 0;
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

 private:
  VehicleParams params_;
  Eigen::MatrixXd M_, C_, K_, T_, B_;
  Eigen::VectorXd fg_, m_full_;
  std::vector<std::string> full_names_;
  std::vector<WheelInfo> wheels_;
  std::vector<BodyInfo> bodies_;
  double total_mass_ = 0.0;
};

}  // namespace railvib::vehicle
