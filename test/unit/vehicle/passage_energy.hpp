// The work-energy balance of an undamped coupled passage (vehicle on a flexible track), shared by the
// vehicle tests. Besides the profile, the contact points move along the deflected rails: the work is
// sum_i int F_i (dz_i - V w_rail'(x_i) dt), the second part from the rail displacement under the moving
// point at the fixed state (trapezoidal in F and in the state). E adds the track's kinetic and strain
// energy and takes the Hertz compression against the rail.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "railvib/track/track_newmark.hpp"
#include "railvib/vehicle/passage.hpp"

namespace railvib::vehicle::passage_test {

struct WorkEnergyBalance {
  double exchanged_j = 0.0;  ///< largest |work| of the contact forces so far
  double worst_j = 0.0;      ///< largest |E - E0 - W|
};

/// Step `run` (on a FlexibleRail) to its end from its first step, balancing E(t) - E(0) against the work.
inline WorkEnergyBalance coupledWorkEnergyBalance(VehiclePassage& run, const VehicleModel& m) {
  const track::TrackNewmark& track = dynamic_cast<FlexibleRail&>(run.rail()).integrator();
  const double C = m.params().hertz_constant_n_m1_5;
  const auto energy = [&]() {
    const Eigen::VectorXd& q = run.displacement();
    const Eigen::VectorXd& v = run.velocity();
    double e = 0.5 * v.dot(m.mass() * v) + 0.5 * q.dot(m.stiffness() * q) - m.gravityLoad().dot(q);
    for (int i = 0; i < m.wheelCount(); ++i) {
      const double delta =
          q[m.wheels()[i].contact_dof] + run.unevennessUnderWheels()[i] - run.railDisplacementUnderWheels()[i];
      if (delta > 0.0) e += 0.4 * C * delta * delta * std::sqrt(delta);
    }
    return e + track.totalEnergy();
  };
  const auto railUnder = [&](const std::vector<double>& x, int i, const Eigen::VectorXd& u) {
    return track.model().railPoint(x[i], m.wheels()[i].rail).displacement(u);
  };
  PassageBlock b;
  run.advance(1, b);
  const double e0 = energy();
  std::vector<double> F = run.contactForces(), z = run.unevennessUnderWheels(), x = run.wheelPositions();
  Eigen::VectorXd u = track.displacement();
  double work = 0.0;
  WorkEnergyBalance out;
  while (!run.finished()) {
    run.advance(1, b);
    const Eigen::VectorXd& u1 = track.displacement();
    const std::vector<double>& x1 = run.wheelPositions();
    for (int i = 0; i < m.wheelCount(); ++i) {
      // the rail's displacement change under the moving point at the fixed (mid-step) state
      const double convected =
          0.5 * (railUnder(x1, i, u) + railUnder(x1, i, u1) - railUnder(x, i, u) - railUnder(x, i, u1));
      work += 0.5 * (F[i] + run.contactForces()[i]) * (run.unevennessUnderWheels()[i] - z[i] - convected);
    }
    F = run.contactForces();
    z = run.unevennessUnderWheels();
    x = x1;
    u = u1;
    out.worst_j = std::max(out.worst_j, std::abs(energy() - e0 - work));
    out.exchanged_j = std::max(out.exchanged_j, std::abs(work));
  }
  return out;
}

}  // namespace railvib::vehicle::passage_test
