// The full-width vehicle (track.width: full): both sides, one wheel per rail per axle, roll of the
// centre-line bodies. Held against the half vehicle it generalises (its motions that are their own
// mirror image are the half vehicle's, twice over), against the closed forms of rigid bodies
// rolling on springs, and against bad files.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "../track/track_test_util.hpp"
#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/vehicle/modal.hpp"
#include "railvib/vehicle/passage.hpp"
#include "vehicle_test_util.hpp"

using namespace railvib;
using namespace railvib::vehicle;
using railvib::track::test::worstRelative;
using railvib::vehicle::test::haren;
using railvib::vehicle::test::sci;

namespace {

/// The scenario's vehicle `name`, half (body_share_per_rail 0.5, haren.yaml) or full width.
VehicleModel scenarioVehicle(const std::string& name, bool full, std::vector<std::string> overrides = {}) {
  overrides.push_back("vehicle.name=" + name);
  if (full) overrides.push_back("track.width=full");
  return VehicleModel(loadVehicleParams(haren(overrides).root()));
}

const char* kVehicles[] = {"t2000", "metro_b"};

/// Reduced coordinate of a full coordinate that is an independent one (T's row a unit vector).
Eigen::Index reducedOf(const VehicleModel& m, Eigen::Index full_dof) {
  Eigen::Index r = -1;
  const double peak = m.transform().row(full_dof).cwiseAbs().maxCoeff(&r);
  EXPECT_EQ(peak, 1.0);
  EXPECT_EQ(m.transform().row(full_dof).cwiseAbs().sum(), 1.0) << "not an independent coordinate";
  return r;
}

const BodyInfo& bodyNamed(const VehicleModel& m, const std::string& name) {
  for (const auto& b : m.bodies()) {
    if (b.name == name) return b;
  }
  ADD_FAILURE() << "no body " << name;
  return m.bodies().front();
}

/// Undamped natural frequencies (Hz) of the submatrices of (K, M) on the reduced coordinates `keep`,
/// every other coordinate held.
std::vector<double> heldFrequencies(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                                    const std::vector<Eigen::Index>& keep) {
  const auto n = static_cast<Eigen::Index>(keep.size());
  Eigen::MatrixXd k(n, n), m(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      k(i, j) = K(keep[i], keep[j]);
      m(i, j) = M(keep[i], keep[j]);
    }
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(k, m);
  std::vector<double> f;
  for (Eigen::Index i = 0; i < n; ++i) f.push_back(std::sqrt(es.eigenvalues()[i]) / (2.0 * M_PI));
  return f;
}

double nearestRelative(const std::vector<double>& fs, double f) {
  double best = 1e300;
  for (double x : fs) best = std::min(best, std::abs(x / f - 1.0));
  return best;
}

}  // namespace

// ------------------------------------------------------------------ the model
TEST(FullWidthVehicle, BothSidesOneWheelPerRailAndRoll) {
  const VehicleModel t = scenarioVehicle("t2000", true);
  // 3 carbodies and 3 bogies (z, theta, phi), 2 x (4 hub motors + 4 treads + 2 trailer wheels),
  // less the two pinned carbody bounces
  EXPECT_EQ(t.fullDofCount(), 6 * 3 + 2 * 10);
  EXPECT_EQ(t.dofCount(), 6 * 3 + 2 * 10 - 2);
  ASSERT_EQ(t.wheelCount(), 12);
  EXPECT_EQ(t.axleCount(), 6);
  for (int a = 0; a < 6; ++a) {
    const WheelInfo& l = t.wheels()[t.wheelIndex(a, track::Rail::Left)];
    const WheelInfo& r = t.wheels()[t.wheelIndex(a, track::Rail::Right)];
    EXPECT_EQ(l.axle, a);
    EXPECT_EQ(r.axle, a);
    EXPECT_EQ(l.rail, track::Rail::Left);
    EXPECT_EQ(r.rail, track::Rail::Right);
    EXPECT_EQ(l.y_m, 0.7175);
    EXPECT_EQ(r.y_m, -0.7175);
    EXPECT_NE(l.contact_dof, r.contact_dof);
    EXPECT_EQ(t.partnerWheel(t.wheelIndex(a, track::Rail::Left)), t.wheelIndex(a, track::Rail::Right));
  }
  EXPECT_EQ(bodyNamed(t, "axle0_tread_right").y_m, -0.7175);
  EXPECT_GE(bodyNamed(t, "front_carbody").phi_dof, 0);
  EXPECT_LT(bodyNamed(t, "axle0_tread_left").phi_dof, 0);
  // the whole tram, and per rail the half vehicle's weight
  const VehicleModel h = scenarioVehicle("t2000", false);
  EXPECT_NEAR(t.totalMass() / (2.0 * h.totalMass()), 1.0, 1e-15);
  EXPECT_NEAR(t.weightPerRail() / h.weightPerRail(), 1.0, 1e-15);
  EXPECT_THROW(h.wheelIndex(0, track::Rail::Right), std::invalid_argument);
  // the metro car's solid wheelsets: both contacts on one body (z, phi)
  const VehicleModel m = scenarioVehicle("metro_b", true);
  EXPECT_EQ(m.dofCount(), 3 * 3 + 4 * 2);
  EXPECT_EQ(m.wheelCount(), 8);
}

// (a) Symmetric special case: the motions that are their own mirror image carry exactly twice the
// half vehicle's mass, stiffness and damping, so the full-width vehicle has every mode of the half
// vehicle (same frequency, same damping), and its other modes are antisymmetric (roll).
TEST(FullWidthVehicle, SymmetricModesAreTheHalfVehicles) {
  for (const std::string name : kVehicles) {
    const std::vector<Mode> half = vehicleModesRigid(scenarioVehicle(name, false));
    const std::vector<Mode> full = vehicleModesRigid(scenarioVehicle(name, true));
    size_t symmetric = 0;
    for (const Mode& m : full) {
      EXPECT_TRUE(m.antisymmetric_share < 1e-12 || m.antisymmetric_share > 1.0 - 1e-12)
          << name << " " << m.name << ": " << m.antisymmetric_share;
      if (m.antisymmetric_share < 0.5) ++symmetric;
    }
    EXPECT_EQ(symmetric, half.size()) << name;
    double worst_f = 0.0, worst_zeta = 0.0;
    for (const Mode& h : half) {
      const Mode* best = nullptr;
      for (const Mode& m : full) {
        if (m.antisymmetric_share > 0.5) continue;
        if (!best || std::abs(m.frequency_hz - h.frequency_hz) < std::abs(best->frequency_hz - h.frequency_hz))
          best = &m;
      }
      ASSERT_NE(best, nullptr);
      worst_f = std::max(worst_f, std::abs(best->frequency_hz / h.frequency_hz - 1.0));
      worst_zeta = std::max(worst_zeta, std::abs(best->damping_ratio - h.damping_ratio));
      // the name too, unless two of the half vehicle's modes share the frequency (the metro car's
      // leading and rear bogies are alike: which one a mode is named after is then arbitrary)
      bool degenerate = false;
      for (const Mode& o : half) {
        degenerate = degenerate || (&o != &h && std::abs(o.frequency_hz / h.frequency_hz - 1.0) < 1e-4);
      }
      if (!degenerate) {
        EXPECT_EQ(best->name, h.name) << name << " " << h.frequency_hz << " Hz";
      }
    }
    EXPECT_LT(worst_f, 1e-9) << name;
    EXPECT_LT(worst_zeta, 1e-9) << name;
    RecordProperty(name + "_worst_relative_frequency_difference", sci(worst_f));
  }
}

// (b) Roll of rigid bodies on springs, every other body held: a body of roll inertia J on springs
// k_i at lateral positions +-y_i rolls at omega^2 = sum 2 k_i y_i^2 / J, uncoupled from its
// bounce and pitch (the springs are mirror images).
TEST(FullWidthVehicle, RollOfARigidBodyOnSpringsIsTheClosedForm) {
  // T2000 leading bogie: motor and trailer primaries and its secondary, each a pair at +-a
  {
    const VehicleModel t = scenarioVehicle("t2000", true);
    const auto& p = t.params();
    const BodyInfo& bogie = bodyNamed(t, "leading_bogie");
    const std::vector<Eigen::Index> keep{reducedOf(t, bogie.z_dof), reducedOf(t, bogie.theta_dof),
                                         reducedOf(t, bogie.phi_dof)};
    double ky2 = 0.0;  // sum of k y^2 over the elements of one side
    for (const auto& e : p.suspensions) {
      if (p.bodies[e.upper_body].name == "leading_bogie" || p.bodies[e.lower_body].name == "leading_bogie")
        ky2 += e.stiffness_n_m * e.y_m * e.y_m;
    }
    const double J = p.bodies[p.bodyIndex("leading_bogie")].roll_inertia_kg_m2;
    const double expected = std::sqrt(2.0 * ky2 / J) / (2.0 * M_PI);
    const auto f = heldFrequencies(t.stiffness(), t.mass(), keep);
    EXPECT_LT(nearestRelative(f, expected), 1e-9) << "T2000 bogie roll " << expected << " Hz";
    RecordProperty("t2000_bogie_roll_hz", sci(expected));
    RecordProperty("t2000_bogie_roll_error", sci(nearestRelative(f, expected)));
    // the roll coordinate is uncoupled: no stiffness between it and bounce or pitch
    EXPECT_EQ(t.stiffness()(keep[2], keep[0]), 0.0);
    EXPECT_EQ(t.stiffness()(keep[2], keep[1]), 0.0);
  }
  // metro car: the carbody on its four air springs at +-1.0 m; a wheelset on its two primaries
  // at +-1.0 m (bogie held) and its two linearised Hertz contacts at +-a: roll
  // omega^2 = 2 (k_p b^2 + k_H a^2) / J_w and bounce 2 (k_p + k_H) / m_w
  {
    const VehicleModel m = scenarioVehicle("metro_b", true);
    const auto& p = m.params();
    const BodyInfo& car = bodyNamed(m, "carbody");
    const auto f_car = heldFrequencies(
        m.stiffness(), m.mass(), {reducedOf(m, car.z_dof), reducedOf(m, car.theta_dof), reducedOf(m, car.phi_dof)});
    const BodySpec& car_spec = p.bodies[p.bodyIndex("carbody")];
    double ks = 0.0, kp = 0.0, ys = 0.0, yp = 0.0;
    for (const auto& e : p.suspensions) {
      (e.stage == "secondary" ? ks : kp) = e.stiffness_n_m;
      (e.stage == "secondary" ? ys : yp) = e.y_m;
    }
    // two air springs per bogie, one each side: four at +-ys
    const double f_car_roll = std::sqrt(4.0 * ks * ys * ys / car_spec.roll_inertia_kg_m2) / (2.0 * M_PI);
    EXPECT_LT(nearestRelative(f_car, f_car_roll), 1e-9) << "metro carbody roll " << f_car_roll << " Hz";

    const auto kH = linearisedHertzStiffness(m);
    const WheelInfo& wl = m.wheels()[m.wheelIndex(0, track::Rail::Left)];
    const WheelInfo& wr = m.wheels()[m.wheelIndex(0, track::Rail::Right)];
    EXPECT_EQ(wl.body, wr.body);             // one body, two contacts
    EXPECT_NEAR(kH[0] / kH[1], 1.0, 1e-12);  // loaded alike
    const Eigen::MatrixXd& B = m.contactSelection();
    const Eigen::VectorXd kv = Eigen::Map<const Eigen::VectorXd>(kH.data(), static_cast<Eigen::Index>(kH.size()));
    const Eigen::MatrixXd K = m.stiffness() + B * kv.asDiagonal() * B.transpose();
    const auto f_ws = heldFrequencies(K, m.mass(), {wl.contact_dof, wr.contact_dof});
    const BodySpec& ws = p.bodies[p.bodyIndex("axle0_wheelset")];
    const double a = p.rail_offset_m;
    const double roll = std::sqrt(2.0 * (kp * yp * yp + kH[0] * a * a) / ws.roll_inertia_kg_m2) / (2.0 * M_PI);
    const double bounce = std::sqrt(2.0 * (kp + kH[0]) / ws.mass_kg) / (2.0 * M_PI);
    EXPECT_LT(nearestRelative(f_ws, roll), 1e-9) << "wheelset roll " << roll << " Hz";
    EXPECT_LT(nearestRelative(f_ws, bounce), 1e-9) << "wheelset bounce " << bounce << " Hz";
    RecordProperty("metro_errors_carbody_roll_wheelset_roll_bounce", sci(nearestRelative(f_car, f_car_roll)) + " " +
                                                                         sci(nearestRelative(f_ws, roll)) + " " +
                                                                         sci(nearestRelative(f_ws, bounce)));
  }
}

// (c) Static: on a rigid track each axle's two wheels carry the same load (the vehicle is
// symmetric), which is the half vehicle's wheel load, and all of them the whole weight.
TEST(FullWidthVehicle, GravitySplitsEquallyBetweenTheWheelsOfAnAxle) {
  for (const std::string name : kVehicles) {
    const VehicleModel h = scenarioVehicle(name, false), f = scenarioVehicle(name, true);
    RigidRail rail;
    std::vector<double> xh, xf;
    for (const auto& w : h.wheels()) xh.push_back(-w.offset_m);
    for (const auto& w : f.wheels()) xf.push_back(-w.offset_m);
    const StaticState sh = staticEquilibrium(h, rail, xh, std::vector<double>(xh.size(), 0.0));
    const StaticState sf = staticEquilibrium(f, rail, xf, std::vector<double>(xf.size(), 0.0));
    EXPECT_NEAR(sf.contact_force_n.sum() / f.weight(), 1.0, 1e-12) << name;
    double worst_split = 0.0, worst_half = 0.0;
    for (int a = 0; a < f.axleCount(); ++a) {
      const double l = sf.contact_force_n[f.wheelIndex(a, track::Rail::Left)];
      const double r = sf.contact_force_n[f.wheelIndex(a, track::Rail::Right)];
      worst_split = std::max(worst_split, std::abs(l / r - 1.0));
      worst_half = std::max(worst_half, std::abs(l / sh.contact_force_n[a] - 1.0));
    }
    EXPECT_LT(worst_split, 1e-12) << name;
    EXPECT_LT(worst_half, 1e-12) << name;
    // and the bodies do not roll
    for (const auto& pose : f.poses(sf.q)) EXPECT_LT(std::abs(pose.roll_rad), 1e-15) << name;
    RecordProperty(name + "_worst_left_right_split", sci(worst_split));
  }
}

// (d) Wheel impedance on a rigid track. In phase (F on both wheels of the axle) the motion is its
// own mirror image and carries twice the half vehicle's impedance under twice its force: per wheel,
// F / v is the half vehicle's. One wheel alone is half in phase plus half in anti-phase, so its
// receptance is the mean: 1 / Z_one = (1 / Z_in + 1 / Z_anti) / 2.
TEST(FullWidthVehicle, WheelImpedanceInPhaseIsTheHalfVehicles) {
  std::vector<double> f;
  for (double v = 1.0; v <= 200.0; v *= 1.07) f.push_back(v);
  double worst_in = 0.0, worst_one = 0.0;
  for (const std::string name : kVehicles) {
    const VehicleModel h = scenarioVehicle(name, false), full = scenarioVehicle(name, true);
    for (int axle : {0, 2}) {
      const auto zh = wheelImpedanceRigid(h, axle, f);
      for (track::Rail rail : {track::Rail::Left, track::Rail::Right}) {
        const int w = full.wheelIndex(axle, rail);
        const auto zin = wheelImpedanceRigid(full, w, f, AxleLoading::InPhase);
        EXPECT_LT(worstRelative(zin, zh), 1e-9) << name << " axle " << axle;
        worst_in = std::max(worst_in, worstRelative(zin, zh));
        const auto zanti = wheelImpedanceRigid(full, w, f, AxleLoading::AntiPhase);
        const auto zone = wheelImpedanceRigid(full, w, f, AxleLoading::OneWheel);
        std::vector<std::complex<double>> mean;
        for (size_t k = 0; k < f.size(); ++k) mean.push_back(2.0 / (1.0 / zin[k] + 1.0 / zanti[k]));
        EXPECT_LT(worstRelative(zone, mean), 1e-9) << name << " axle " << axle;
        worst_one = std::max(worst_one, worstRelative(zone, mean));
        // anti-phase differs: the roll modes are not the bounce ones
        EXPECT_GT(worstRelative(zanti, zin), 1e-2) << name << " axle " << axle;
      }
    }
    EXPECT_THROW(wheelImpedanceRigid(h, 0, f, AxleLoading::AntiPhase), std::invalid_argument);
  }
  RecordProperty("worst_in_phase_vs_half", sci(worst_in));
  RecordProperty("worst_one_wheel_vs_superposition", sci(worst_one));
}

// (d, flexible) On the full-width track, in phase: each rail carries the half track's load and the
// vehicle the half vehicle's, so the impedance is the half vehicle's on the half track.
TEST(FullWidthVehicle, WheelImpedanceOnTheFlexibleTrackInPhaseIsTheHalfChains) {
  std::vector<double> f;
  for (double v = 2.0; v <= 200.0; v *= 1.6) f.push_back(v);
  const Config ch = haren({"track.extent.mode=fixed", "track.extent.x_min_m=-30", "track.extent.x_max_m=40"});
  const Config cf =
      haren({"track.extent.mode=fixed", "track.extent.x_min_m=-30", "track.extent.x_max_m=40", "track.width=full"});
  const VehicleModel h(loadVehicleParams(ch.root())), full(loadVehicleParams(cf.root()));
  const auto th = track::loadTrackParams(ch.root()), tf = track::loadTrackParams(cf.root());
  const auto zh = wheelImpedanceFlexible(h, th, 0, f);
  const auto zin =
      wheelImpedanceFlexible(full, tf, full.wheelIndex(0, track::Rail::Right), f, 0.0, AxleLoading::InPhase);
  EXPECT_LT(worstRelative(zin, zh), 1e-9);
  RecordProperty("worst_in_phase_vs_half_chain", sci(worstRelative(zin, zh)));
  // a vehicle and a track of different widths do not go together
  EXPECT_THROW(wheelImpedanceFlexible(full, th, 0, f), std::invalid_argument);
}

// Flexible-track modes: the full-width vehicle on the full-width local track has every mode of the
// half chain.
TEST(FullWidthVehicle, FlexibleTrackModesContainTheHalfChains) {
  const VehicleModel h = scenarioVehicle("t2000", false), full = scenarioVehicle("t2000", true);
  const auto th = track::loadTrackParams(haren().root());
  const auto tf = track::loadTrackParams(haren({"track.width=full"}).root());
  ModalOptions options;
  options.margin_m = 2.0;  // a shorter local track than the tool's (6 m): the same comparison, cheaper
  const auto mh = vehicleModesFlexible(h, th, options);
  const auto mf = vehicleModesFlexible(full, tf, options);
  double worst = 0.0;
  for (const Mode& m : mh) {
    double best = 1e300;
    for (const Mode& x : mf) {
      if (x.antisymmetric_share < 0.5) best = std::min(best, std::abs(x.frequency_hz / m.frequency_hz - 1.0));
    }
    worst = std::max(worst, best);
  }
  // Round-off of two different dense eigenproblems: an eigenvalue comes to ~eps x the largest one
  // (the rail's stiffest element modes), so the 2.5 Hz car-body modes are the least exact (1.8e-8
  // measured); a wrong coupling would move them by far more (the anti-phase roll modes are others).
  EXPECT_LT(worst, 1e-6);
  RecordProperty("worst_relative_frequency_difference", sci(worst));
  bool roll = false;
  for (const Mode& x : mf) roll = roll || x.name == "car-body roll";
  EXPECT_TRUE(roll);
}

// ------------------------------------------------------------------ bad input
namespace {
std::string fullWidthError(std::vector<std::string> overrides) {
  overrides.push_back("track.width=full");
  try {
    loadVehicleParams(haren(overrides).root());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

/// The T2000's suspensions as a YAML list, without element `skip`.
std::string t2000SuspensionsWithout(size_t skip) {
  const VehicleParams p = loadVehicleParams(haren().root());
  std::ostringstream s;
  s << std::setprecision(17) << "[";
  for (size_t i = 0; i < p.suspensions.size(); ++i) {
    if (i == skip) continue;
    const auto& e = p.suspensions[i];
    s << (s.tellp() > 1 ? ", " : "") << "{stage: " << e.stage << ", upper: " << p.bodies[e.upper_body].name
      << ", lower: " << p.bodies[e.lower_body].name << ", x_m: " << e.x_m << ", y_m: " << e.y_m << "}";
  }
  s << "]";
  return s.str();
}
}  // namespace

TEST(FullWidthVehicle, RefusesBadFiles) {
  const std::string t = "vehicles.t2000.";
  struct Case {
    std::vector<std::string> overrides;
    const char* key;
    const char* reason;
  } cases[] = {
      // a decimal point slipped: 7.175 m from the centre line
      {{t + "bodies.axle0_tread.y_m=7.175"}, "bodies.axle0_tread.y_m", "wider than rail vehicles"},
      // the wheels off the rails: the gauge is not the vehicle's
      {{"site.rail_gauge_m=1.5"}, "bodies.axle0_tread.y_m", "not on its rail"},
      // a full-width body on the centre line without its roll inertia
      {{t + "bodies.roof_unit={kind: carbody, x_m: 1.0, mass_kg: 300.0, pitch_inertia_kg_m2: 50.0, "
            "extent_m: [0.0, 2.0]}"},
       "bodies.roof_unit.roll_inertia_kg_m2",
       "missing"},
      // a roll inertia on a body of one side
      {{t + "bodies.axle0_tread={kind: tread, x_m: 0.0, y_m: 0.7175, mass_kg: 80.0, roll_inertia_kg_m2: 1.0}"},
       "bodies.axle0_tread.roll_inertia_kg_m2",
       "no roll"},
      // an element beside the side body it holds
      {{t + "bodies.axle1_trailer_wheel={kind: wheel, x_m: 1.6667, y_m: 0.6, mass_kg: 160.0}"},
       "suspensions[5].y_m",
       "beside body"},
      // the central carbody without its secondary: the pins leave its roll free (a mechanism)
      {{t + "suspensions=" + t2000SuspensionsWithout(1)}, "vehicles.t2000.bodies", "mechanism"},
  };
  for (const Case& c : cases) {
    const std::string msg = fullWidthError(c.overrides);
    EXPECT_NE(msg.find(c.key), std::string::npos) << c.overrides.front() << ": " << msg;
    EXPECT_NE(msg.find(c.reason), std::string::npos) << c.overrides.front() << ": " << msg;
    EXPECT_NE(msg.find("[file "), std::string::npos) << msg;
  }
  // the mechanism names the body that rolls freely, and a roll stiffness at the pins removes it
  EXPECT_NE(fullWidthError({t + "suspensions=" + t2000SuspensionsWithout(1)}).find("central_carbody"),
            std::string::npos);
  const std::string pins =
      t +
      "joints=[{type: vertical_pin, bodies: [front_carbody, central_carbody], x_m: 6.2333, "
      "pitch_stiffness_n_m_rad: 2.0e6, pitch_damping_n_m_s_rad: 0.0, roll_stiffness_n_m_rad: 1.0e6}, "
      "{type: vertical_pin, bodies: [central_carbody, rear_carbody], x_m: 10.4333, pitch_stiffness_n_m_rad: "
      "2.0e6, pitch_damping_n_m_s_rad: 0.0}]";
  EXPECT_EQ(fullWidthError({t + "suspensions=" + t2000SuspensionsWithout(1), pins}), "");
  // the half vehicle is held in roll by nothing it models: the same file is fine there
  EXPECT_NO_THROW(loadVehicleParams(haren({t + "suspensions=" + t2000SuspensionsWithout(1)}).root()));
  EXPECT_EQ(fullWidthError({}), "");
  EXPECT_EQ(fullWidthError({"vehicle.name=metro_b"}), "");
}
