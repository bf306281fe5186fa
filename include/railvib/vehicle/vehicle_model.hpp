// railvib/vehicle: linear multibody model of a vehicle described as data
// (vehicle_params.hpp): the half vehicle on one rail, or the full width on both.
//
// Vertical model: bounce and pitch (half width), and roll of the centre-line
// bodies (full width). Vertical displacements are positive DOWNWARD (track
// convention), pitch is positive nose-up (rear end down), roll positive when
// the left side (y > 0, Rail::Left, the building side) goes down: the downward
// displacement of a point of a body at offset s behind the front axle and
// lateral position y is w(s, y) = z + (s - s_c) * theta + y * phi, s_c the
// body's reference point (its centre of mass) -- the track's sleeper
// convention (a seat at y moves down by heave + y roll).
//
// Full width: every centre-line body has z, (theta), phi and counts wholly; a
// body or element of one side (y > 0 in the file) is instantiated twice, at
// +y (`<name>_left`) and mirrored at -y (`<name>_right`); wheels are one per
// rail per axle, axle-major (wheel 2a left, 2a + 1 right). A centre-line wheel
// body (a solid wheelset) is described by the displacements of its two contact
// points (w_left = z + a phi, w_right = z - a phi, a = rail_offset_m), so that
// every contact is one reduced DOF. The half vehicle is the symmetric special
// case: in the motions that are their own mirror image the full-width
// matrices are exactly twice the half vehicle's with body_share_per_rail 0.5.
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
  /// Lateral position of the reference point (m): 0 on the centre line; full width: > 0 the left
  /// instance of a body of one side, < 0 its mirror image (half width: the file's y_m).
  double y_m = 0.0;
  Eigen::Index phi_dof = -1;  ///< full-coordinate index of the roll (full width, centre-line bodies; else -1)
  int spec = -1;              ///< its entry in params().bodies
};

struct WheelInfo {
  int axle = 0;
  AxleType type = AxleType::Motor;
  double offset_m = 0.0;  ///< behind the front axle
  double radius_m = 0.34;
  /// Mass of the body that carries the contact (tread or trailer wheel), kg.
  double contact_mass_kg = 0.0;
  int bogie = 0;  ///< index of its bogie among the bogies (-1: none)
  int body = -1;  ///< index of the contact body in bodies()
  /// Reduced-coordinate DOF carrying the contact: the tread's or wheel's bounce, or (full width, a
  /// centre-line wheelset) the displacement of its contact point on this wheel's rail.
  Eigen::Index contact_dof = -1;
  /// The rail under the contact: the half vehicle runs on the left rail (the half track's).
  track::Rail rail = track::Rail::Left;
  double y_m = 0.0;  ///< lateral position of the contact (m): +-rail_offset_m
};

/// Pose of a body (per sample, for the node's tf): downward displacement and nose-up pitch.
struct BodyPose {
  double offset_m = 0.0;                 ///< reference point behind the front axle
  double vertical_displacement_m = 0.0;  ///< positive downward (from the unloaded reference)
  double pitch_rad = 0.0;                ///< positive nose-up
  double roll_rad = 0.0;                 ///< positive left side down (full width; 0 otherwise)
  double lateral_m = 0.0;                ///< lateral position of the reference point (BodyInfo::y_m)
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

  bool fullWidth() const { return params_.fullWidth(); }
  /// Wheels: one per axle (half width) or one per rail per axle (full width, axle-major).
  int wheelCount() const { return static_cast<int>(wheels_.size()); }
  int axleCount() const { return params_.axleCount(); }
  /// Index in wheels() of the wheel of `axle` on `rail` (throws std::invalid_argument for the right
  /// rail of the half vehicle, std::out_of_range for an unknown axle).
  int wheelIndex(int axle, track::Rail rail) const;
  /// The rail under each wheel, in the order of wheels() (the half vehicle: Rail::Left only).
  std::vector<track::Rail> wheelRails() const;
  /// The other wheel of a wheel's axle (full width), or -1 (half width).
  int partnerWheel(int wheel) const;
  const std::vector<WheelInfo>& wheels() const { return wheels_; }
  const std::vector<BodyInfo>& bodies() const { return bodies_; }
  /// Contact selection: column i = unit vector on wheel i's contact DOF (n x nw).
  const Eigen::MatrixXd& contactSelection() const { return B_; }

  /// Mass the model carries (kg: per rail for the half vehicle, the whole vehicle at full width) and
  /// its weight (N): the sum of the static contact forces.
  double totalMass() const { return total_mass_; }
  double weight() const { return total_mass_ * params_.gravity_m_s2; }
  /// Total mass per rail (kg) and weight per rail (N).
  double totalMassPerRail() const { return fullWidth() ? 0.5 * total_mass_ : total_mass_; }
  double weightPerRail() const { return totalMassPerRail() * params_.gravity_m_s2; }

  /// The mirror image (y -> -y) of a full-coordinate vector x is x'[i] = mirrorSign()[i] *
  /// x[mirrorDof()[i]]: left and right instances swap, roll changes sign (half width: identity).
  const std::vector<Eigen::Index>& mirrorDof() const { return mirror_dof_; }
  const Eigen::VectorXd& mirrorSign() const { return mirror_sign_; }
  /// The same in reduced coordinates (a wheelset's two contact points swap).
  const std::vector<Eigen::Index>& reducedMirrorDof() const { return reduced_mirror_dof_; }
  const Eigen::VectorXd& reducedMirrorSign() const { return reduced_mirror_sign_; }

  /// Poses of all bodies for a reduced displacement vector.
  std::vector<BodyPose> poses(const Eigen::VectorXd& q) const;
  /// Display name of a bogie or the bogie of a wheel part ("leading bogie"), or "vehicle".
  std::string bogieLabel(const BodyInfo& body) const;

 private:
  VehicleParams params_;
  Eigen::MatrixXd M_, C_, K_, T_, B_;
  Eigen::VectorXd fg_, m_full_, mirror_sign_, reduced_mirror_sign_;
  std::vector<Eigen::Index> mirror_dof_, reduced_mirror_dof_;
  std::vector<std::string> full_names_;
  std::vector<WheelInfo> wheels_;
  std::vector<BodyInfo> bodies_;
  double total_mass_ = 0.0;
};

/// The weight per rail shared equally by the axles (N, one per axle): the constant moving loads on
/// one rail that stand for the vehicle in track-only runs (`railvib_tool moving-load`, the track
/// scenario).
std::vector<double> uniformStaticWheelLoadsPerRail(const VehicleModel& model);

}  // namespace railvib::vehicle
