// Resilient wheels (issue 33, a source-side mitigation measure; docs/vehicle.md, "Resilient wheels"):
// vehicles.<name>.resilient_wheels turns each rigid wheel carrying a contact into a hub and a tread on a
// resilient ring. Held against the file's vehicle when absent or disabled (the same matrices), the
// conservation of mass and static wheel loads, the closed form of the wheel's chain (impedance at the
// tread and the ring's resonance), the loader's refusals, and the coupled passage over the defect
// (bounded, and the work-energy balance of the undamped system).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "passage_energy.hpp"
#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/track/track_newmark.hpp"
#include "railvib/vehicle/modal.hpp"
#include "railvib/vehicle/passage.hpp"
#include "railvib/vehicle/resilient_wheel.hpp"
#include "vehicle_test_util.hpp"

using namespace railvib;
using namespace railvib::vehicle;
using railvib::vehicle::test::haren;
using railvib::vehicle::test::with;

namespace {

VehicleModel modelOf(const std::vector<std::string>& overrides) {
  return VehicleModel(loadVehicleParams(haren(overrides).root()));
}

/// The T2000's trailer wheels made resilient with the motor wheels' tread and ring (the catalogue's
/// measure, config/mitigation.yaml).
std::vector<std::string> trailerMeasure(const std::string& vehicle = "t2000", const std::string& wheels = "rigid") {
  const std::string r = "vehicles." + vehicle + ".resilient_wheels.";
  return {r + "enabled=true", r + "wheels=" + wheels, r + "tread_mass_kg=80.0", r + "stiffness_n_m=145.0e6",
          r + "damping_n_s_m=3.0e3"};
}

/// A rig: a free point mass M on a primary spring over one wheel on the rail, no carbody. Made
/// resilient, it is exactly the closed form's chain with a free mass on top (resilient_wheel.hpp).
std::vector<std::string> rig(double damping_scale) {
  return {"vehicle.name=rig",
          "vehicles.rig={description: rig, contact: {hertz_constant_n_m1_5: 1.0e11}, "
          "bodies: {sprung: {kind: wheel_hub, x_m: 0.0, y_m: 0.7175, mass_kg: 900.0}, "
          "wheel: {kind: wheel, x_m: 0.0, y_m: 0.7175, mass_kg: 400.0}}, "
          "suspension_stages: {primary: {stiffness_n_m: 20.0e6, damping_n_s_m: " +
              std::to_string(15.0e3 * damping_scale) +
              "}}, suspensions: [{stage: primary, upper: sprung, lower: wheel, x_m: 0.0, y_m: 0.7175}], "
              "wheels: [{name: axle0, body: wheel, type: trailer, radius_m: 0.34}], "
              "resilient_wheels: {enabled: true, wheels: rigid, tread_mass_kg: 60.0, stiffness_n_m: 120.0e6, "
              "damping_n_s_m: " +
              std::to_string(4.0e3 * damping_scale) + "}}"};
}

std::vector<double> logFrequencies(double f0, double f1, int n) {
  std::vector<double> f;
  for (int k = 0; k < n; ++k) f.push_back(f0 * std::pow(f1 / f0, static_cast<double>(k) / (n - 1)));
  return f;
}

double staticLoad(const VehicleModel& m, int wheel) {
  const auto k = linearisedHertzStiffness(m);
  // k_H = 1.5 C^(2/3) F^(1/3): the static load back from the linearised stiffness
  const double C = m.params().hertz_constant_n_m1_5;
  return std::pow(k[static_cast<size_t>(wheel)] / (1.5 * std::pow(C, 2.0 / 3.0)), 3.0);
}

// Absent or `enabled: false`: the file's vehicle, the same matrices to the bit (the section's values
// are validated all the same).
TEST(ResilientWheels, AbsentOrDisabledIsTheFilesVehicle) {
  for (const std::string v : {"t2000", "metro_b"}) {
    for (const std::string width : {"half", "full"}) {
      const std::vector<std::string> base{"vehicle.name=" + v, "track.width=" + width};
      const VehicleModel plain = modelOf(base);
      std::vector<std::string> off = with(base, trailerMeasure(v, "all"));
      off[2] = "vehicles." + v + ".resilient_wheels.enabled=false";
      const VehicleModel disabled = modelOf(off);
      EXPECT_FALSE(disabled.params().resilient_wheels.has_value());
      EXPECT_TRUE(plain.mass() == disabled.mass()) << v << " " << width;
      EXPECT_TRUE(plain.stiffness() == disabled.stiffness()) << v << " " << width;
      EXPECT_TRUE(plain.damping() == disabled.damping()) << v << " " << width;
      EXPECT_TRUE(plain.transform() == disabled.transform()) << v << " " << width;
      EXPECT_EQ(plain.bodies().size(), disabled.bodies().size());
    }
  }
}

// The conversion moves no mass: the same total, the same static wheel loads; the trailer wheels are
// hubs over treads carrying the contact; the motor wheels' rings are untouched by `rigid` and take the
// section's ring with `all`.
TEST(ResilientWheels, RigidWheelsBecomeHubsOverTreads) {
  const VehicleModel plain = modelOf({});
  const VehicleModel rw = modelOf(trailerMeasure());
  ASSERT_TRUE(rw.params().resilient_wheels.has_value());
  EXPECT_EQ(rw.dofCount(), plain.dofCount() + 2);
  EXPECT_NEAR(rw.totalMass(), plain.totalMass(), 1e-9);
  for (int w : {1, 4}) {
    const BodyInfo& tread = rw.bodies()[static_cast<size_t>(rw.wheels()[w].body)];
    EXPECT_EQ(tread.kind, BodyKind::Tread);
    EXPECT_EQ(tread.name, std::string("axle") + std::to_string(w) + "_trailer_wheel_tread");
    EXPECT_DOUBLE_EQ(rw.wheels()[w].contact_mass_kg, 80.0);
    const auto chain = resilientWheelChain(rw, w);
    ASSERT_TRUE(chain.has_value());
    EXPECT_DOUBLE_EQ(chain->hub_mass_kg, 80.0);
    EXPECT_EQ(chain->upper, w == 1 ? "leading_bogie" : "rear_bogie");
    EXPECT_DOUBLE_EQ(chain->primary_stiffness_n_m, 5.88e6);
  }
  // The wheel loads still carry the weight. The T2000's carbodies, pinned with pitch springs, are
  // statically indeterminate, so the ring in series with the trailer primary (145 MN/m with 5.88) moves
  // a little load: 5e-5 to 8.5e-5 of each wheel's (the metro car, determinate, below: 1e-9).
  double sum = 0.0;
  for (int w = 0; w < plain.wheelCount(); ++w) {
    sum += staticLoad(rw, w);
    EXPECT_NEAR(staticLoad(rw, w) / staticLoad(plain, w), 1.0, 2e-4) << w;
  }
  EXPECT_NEAR(sum / rw.weight(), 1.0, 1e-9);
  // a softer ring on every wheel
  std::vector<std::string> soft = trailerMeasure("t2000", "all");
  soft[3] = "vehicles.t2000.resilient_wheels.stiffness_n_m=60.0e6";
  const VehicleModel all = modelOf(soft);
  for (int w = 0; w < all.wheelCount(); ++w) {
    EXPECT_DOUBLE_EQ(resilientWheelChain(all, w)->ring_stiffness_n_m, 60.0e6) << w;
  }
  EXPECT_DOUBLE_EQ(resilientWheelChain(rw, 0)->ring_stiffness_n_m, 145.0e6);
  // the metro car's solid wheelsets: a tread on each rail, the hub on the centre line, at both widths
  for (const std::string width : {"half", "full"}) {
    const std::vector<std::string> base{"vehicle.name=metro_b", "track.width=" + width};
    const VehicleModel mp = modelOf(base);
    const VehicleModel mr = modelOf(with(base, trailerMeasure("metro_b")));
    EXPECT_NEAR(mr.totalMass(), mp.totalMass(), 1e-9) << width;
    EXPECT_EQ(mr.wheelCount(), mp.wheelCount());
    for (int w = 0; w < mr.wheelCount(); ++w) {
      EXPECT_EQ(mr.bodies()[static_cast<size_t>(mr.wheels()[w].body)].kind, BodyKind::Tread);
      EXPECT_NEAR(staticLoad(mr, w) / staticLoad(mp, w), 1.0, 1e-9) << width << " " << w;
    }
    // a tread more per wheelset at half width (the modelled rail's), two at full width (the hub's
    // bounce and roll take the place of the wheelset's two contact points)
    EXPECT_EQ(mr.dofCount(), mp.dofCount() + (width == "half" ? 4 : 8)) << width;
  }
}

// The rig (a free mass on a primary over a resilient wheel: exactly the closed form's chain): the
// impedance at the tread on the rigid track against the closed form over 1 Hz - 2 kHz, and the three
// natural frequencies (undamped) against the cubic's roots. Both are the same linear algebra done two
// ways, so they agree to round-off; the tolerance (1e-8, the brief asks 1 %) leaves room for the
// ill-conditioned frequencies near the chain's anti-resonances.
TEST(ResilientWheels, RigWheelImpedanceAndRingResonanceAreTheClosedForms) {
  const VehicleModel m = modelOf(rig(1.0));
  ASSERT_EQ(m.dofCount(), 3);
  const auto chain = resilientWheelChain(m, 0);
  ASSERT_TRUE(chain.has_value());
  EXPECT_DOUBLE_EQ(chain->tread_mass_kg, 60.0);
  EXPECT_DOUBLE_EQ(chain->hub_mass_kg, 340.0);
  EXPECT_DOUBLE_EQ(chain->upper_mass_kg, 900.0);
  // k_H = 1.5 C^(2/3) W^(1/3), W the rig's weight
  const double W = 1300.0 * 9.81;
  EXPECT_NEAR(chain->hertz_stiffness_n_m / (1.5 * std::pow(1.0e11, 2.0 / 3.0) * std::cbrt(W)), 1.0, 1e-9);
  const std::vector<double> f = logFrequencies(1.0, 2000.0, 400);
  const auto Z = wheelImpedanceRigid(m, 0, f);
  double worst = 0.0;
  for (size_t k = 0; k < f.size(); ++k) {
    const auto zc = resilientWheelImpedance(*chain, f[k], ChainTop::FreeMass);
    worst = std::max(worst, std::abs(Z[k] - zc) / std::abs(zc));
  }
  std::printf("[ figures  ] rig: |Z - Z_closed| / |Z_closed| <= %.3g over 1-2000 Hz\n", worst);
  EXPECT_LT(worst, 1e-8);

  const VehicleModel undamped = modelOf(rig(0.0));
  const auto chain0 = resilientWheelChain(undamped, 0);
  const std::vector<double> fc = resilientWheelFrequencies(*chain0, ChainTop::FreeMass);
  const auto modes = vehicleModesRigid(undamped);
  ASSERT_EQ(modes.size(), 3u);
  ASSERT_EQ(fc.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    std::printf("[ figures  ] rig mode %zu: %.6f Hz (model), %.6f Hz (closed form), %s\n", k, modes[k].frequency_hz,
                fc[k], modes[k].name.c_str());
    EXPECT_NEAR(modes[k].frequency_hz / fc[k], 1.0, 1e-9) << k;
  }
  EXPECT_EQ(modes.back().body, "wheel_tread");
}

// The T2000's trailer wheel made resilient, against the chain's closed form with the bogie blocked.
// Below ~30 Hz the Hertz spring (0.9 GN/m) governs the impedance on the rigid track and both agree
// within 1.2 %; around the hub's own mode (201 Hz blocked) the bogie (900 kg per rail, the other
// wheel, the secondary) moves with the hub and the blocked closed form is 3.3 % off; above 250 Hz
// the bogie no longer follows and the closed form holds within 1 %. The ring's resonance is the
// tread's mode of the model.
TEST(ResilientWheels, T2000TrailerWheelAgainstTheBlockedBogieClosedForm) {
  const VehicleModel m = modelOf(trailerMeasure());
  const auto chain = resilientWheelChain(m, 1);
  ASSERT_TRUE(chain.has_value());
  const std::vector<double> f = logFrequencies(1.0, 2000.0, 400);
  const auto Z = wheelImpedanceRigid(m, 1, f);
  double worst = 0.0, worst_above = 0.0;
  for (size_t k = 0; k < f.size(); ++k) {
    const auto zc = resilientWheelImpedance(*chain, f[k], ChainTop::Blocked);
    const double dev = std::abs(Z[k] - zc) / std::abs(zc);
    worst = std::max(worst, dev);
    if (f[k] >= 250.0) worst_above = std::max(worst_above, dev);
  }
  const std::vector<double> fc = resilientWheelFrequencies(*chain, ChainTop::Blocked);
  double f_tread = 0.0;
  for (const Mode& mode : vehicleModesRigid(m)) {
    if (mode.body == chain->tread) f_tread = mode.frequency_hz;
  }
  std::printf(
      "[ figures  ] T2000 wheel 1 resilient: |Z - Z_blocked| / |Z_blocked| <= %.3g over 250-2000 Hz, %.3g over "
      "1-2000 Hz; ring resonance %.3f Hz (model) vs %.3f Hz (closed form, bogie blocked), hub %.3f Hz\n",
      worst_above, worst, f_tread, fc.back(), fc.front());
  EXPECT_LT(worst_above, 0.01);
  EXPECT_LT(worst, 0.05);
  EXPECT_NEAR(f_tread / fc.back(), 1.0, 1e-3);
}

// Refused with the key path, the value's reason and the file.
TEST(ResilientWheels, RefusesBadValues) {
  const std::string r = "vehicles.t2000.resilient_wheels.";
  struct Case {
    std::vector<std::string> overrides;
    const char* key;
    const char* reason;
  } cases[] = {
      {with(trailerMeasure(), {r + "tread_mass_kg=160.0"}), "resilient_wheels.tread_mass_kg", "below the mass"},
      {with(trailerMeasure(), {r + "tread_mass_kg=-5.0"}), "resilient_wheels.tread_mass_kg", "out of range"},
      {with(trailerMeasure(), {r + "stiffness_n_m=1.0e5"}), "resilient_wheels.stiffness_n_m", "out of range"},
      {with(trailerMeasure(), {r + "stiffness_n_m=1.0e11"}), "resilient_wheels.stiffness_n_m", "out of range"},
      {with(trailerMeasure(), {r + "damping_n_s_m=-1.0"}), "resilient_wheels.damping_n_s_m", "out of range"},
      {with(trailerMeasure(), {r + "wheels=some"}), "resilient_wheels.wheels", "unknown value"},
      // disabled, a bad value is refused all the same
      {with(trailerMeasure(), {r + "enabled=false", r + "tread_mass_kg=200.0"}), "resilient_wheels.tread_mass_kg",
       "below the mass"},
      // a wheelset has a tread on each rail: below half its 1420 kg
      {with(trailerMeasure("metro_b"), {"vehicle.name=metro_b", "vehicles.metro_b.resilient_wheels.tread_mass_kg=710"}),
       "metro_b.resilient_wheels.tread_mass_kg", "(0, 710) kg"},
      // nothing to change
      {with({"vehicle.name=metro_b"}, {"vehicles.metro_b.resilient_wheels={enabled: true, wheels: resilient, "
                                       "stiffness_n_m: 1.0e8, damping_n_s_m: 1.0e3}"}),
       "metro_b.resilient_wheels.wheels", "no resilient wheel"},
      {with(trailerMeasure(), {r + "wheels=resilient"}), "resilient_wheels.tread_mass_kg", "rings already fitted"},
  };
  for (const Case& c : cases) {
    try {
      const Config cfg = haren(c.overrides);
      loadVehicleParams(cfg.root());
      ADD_FAILURE() << "accepted: " << c.overrides.back();
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.key), std::string::npos) << c.overrides.back() << ": " << msg;
      EXPECT_NE(msg.find(c.reason), std::string::npos) << c.overrides.back() << ": " << msg;
      EXPECT_NE(msg.find("[file "), std::string::npos) << msg;
    }
  }
}

// The front bogie over the defect: the motor wheel (axle 0) then the trailer wheel (axle 1).
const std::vector<std::string> kFrontBogieOverDefect = {"simulation.front_axle_start_m=-0.3",
                                                        "simulation.duration_s=0.27"};

struct MeasureRun {
  explicit MeasureRun(const std::vector<std::string>& overrides)
      : cfg(haren(overrides)),
        model(loadVehicleParams(cfg.root())),
        pp(loadPassageParams(cfg.root())),
        tp(track::loadTrackParams(cfg.root())),
        unevenness(loadUnevennessParams(cfg.root()), tp.layout.x_min_m, tp.layout.x_max_m) {}
  Config cfg;
  VehicleModel model;
  PassageParams pp;
  track::TrackParams tp;
  Unevenness unevenness;
};

/// Peak contact force of each wheel (N) and the largest vehicle energy (J) over the run.
struct Peaks {
  std::vector<double> force_n;
  double static_n = 0.0;
  bool finite = true;
};

Peaks runPeaks(MeasureRun& s) {
  VehiclePassage run(s.model, s.unevenness, s.pp, makeRailSupport(s.pp, s.tp));
  Peaks p;
  p.force_n.assign(static_cast<size_t>(s.model.wheelCount()), 0.0);
  PassageBlock b;
  run.advance(1, b);
  p.static_n = *std::max_element(run.contactForces().begin(), run.contactForces().end());
  while (!run.finished()) {
    run.advance(1, b);
    for (int i = 0; i < s.model.wheelCount(); ++i) {
      const double f = run.contactForces()[i];
      p.finite = p.finite && std::isfinite(f);
      p.force_n[static_cast<size_t>(i)] = std::max(p.force_n[static_cast<size_t>(i)], f);
    }
  }
  return p;
}

// The 1 mm x 5 mm defect under the front bogie, CLM (dt 1e-5 s, the paper's and the scenario's), with
// and without the resilient trailer wheels, half and full width: bounded (finite, < 10 x the static
// load), the motor wheel's impact unchanged within 2 % (its own wheel is the same), and the figures.
TEST(ResilientWheels, ContactForcePeaksOverTheDefect) {
  for (const std::string width : {"half", "full"}) {
    const std::vector<std::string> base = with(kFrontBogieOverDefect, {"track.width=" + width});
    MeasureRun without(base);
    MeasureRun with_rw(with(base, trailerMeasure()));
    const Peaks a = runPeaks(without), b = runPeaks(with_rw);
    ASSERT_TRUE(a.finite && b.finite);
    const size_t motor = 0, trailer = width == "half" ? 1 : 2;  // full width: axle-major, left rail
    std::printf(
        "[ figures  ] %s width, CLM: peak contact force motor wheel %.2f -> %.2f kN, trailer wheel %.2f -> "
        "%.2f kN (rigid -> resilient trailer wheels)\n",
        width.c_str(), a.force_n[motor] / 1e3, b.force_n[motor] / 1e3, a.force_n[trailer] / 1e3,
        b.force_n[trailer] / 1e3);
    for (double f : b.force_n) EXPECT_LT(f, 10.0 * b.static_n);
    EXPECT_NEAR(b.force_n[motor] / a.force_n[motor], 1.0, 0.02);
    EXPECT_GT(b.force_n[trailer], 1.5 * 21.82e3);  // the trailer wheel does hit the defect
  }
}

// Undamped vehicle (its rings too) on the undamped CLM track, half width, the resilient trailer wheels:
// the coupled system's energy changes by the work of the contact forces (passage_energy.hpp), within
// 1e-3 of it, as the file's vehicle does (2.5e-4, test_passage_full_width).
TEST(ResilientWheels, UndampedCoupledSystemWorkEnergyBalance) {
  const std::string t = "vehicles.t2000.suspension_stages.";
  MeasureRun s(with(
      with(kFrontBogieOverDefect, trailerMeasure()),
      {"simulation.duration_s=0.25", "simulation.contact_tolerance=1.0e-12",
       "vehicles.t2000.resilient_wheels.damping_n_s_m=0", t + "secondary.damping_n_s_m=0",
       t + "motor_primary.damping_n_s_m=0", t + "trailer_primary.damping_n_s_m=0", t + "resilient_ring.damping_n_s_m=0",
       "track.ends.absorbing_length_m=0", "track.railpad.damping_n_s_m=0", "track.ballast.damping_n_s_m=0",
       "track.foundation.clm.damping_n_s_m=0", "track.foundation.clm.coupling_damping_n_s_m=0"}));
  ASSERT_EQ(s.model.damping().norm(), 0.0);
  VehiclePassage run(s.model, s.unevenness, s.pp, makeRailSupport(s.pp, s.tp));
  const passage_test::WorkEnergyBalance balance = passage_test::coupledWorkEnergyBalance(run, s.model);
  std::printf("[ figures  ] undamped, CLM, resilient trailer wheels: work %.4g J, worst |E - E0 - W| %.3g J (%.3g)\n",
              balance.exchanged_j, balance.worst_j, balance.worst_j / balance.exchanged_j);
  EXPECT_GT(balance.exchanged_j, 1.0);
  EXPECT_LT(balance.worst_j, 1e-3 * balance.exchanged_j);
}

// The same on the rigid track (the vehicle's energy and the Hertz potential against the work of the
// profile): the undamped rings chatter on the 1 mm defect, so the bound is the full-width test's 1e-3.
TEST(ResilientWheels, UndampedRigidTrackWorkEnergyBalance) {
  const std::string t = "vehicles.t2000.suspension_stages.";
  MeasureRun s(
      with(with(kFrontBogieOverDefect, trailerMeasure()),
           {"simulation.vehicle_track=rigid", "vehicles.t2000.resilient_wheels.damping_n_s_m=0",
            t + "secondary.damping_n_s_m=0", t + "motor_primary.damping_n_s_m=0", t + "trailer_primary.damping_n_s_m=0",
            t + "resilient_ring.damping_n_s_m=0", "simulation.contact_tolerance=1.0e-12"}));
  const VehicleModel& m = s.model;
  ASSERT_EQ(m.damping().norm(), 0.0);
  VehiclePassage run(m, s.unevenness, s.pp, makeRailSupport(s.pp, s.tp));
  const double C = m.params().hertz_constant_n_m1_5;
  const auto energy = [&]() {
    const Eigen::VectorXd& q = run.displacement();
    const Eigen::VectorXd& v = run.velocity();
    double e = 0.5 * v.dot(m.mass() * v) + 0.5 * q.dot(m.stiffness() * q) - m.gravityLoad().dot(q);
    for (int i = 0; i < m.wheelCount(); ++i) {
      const double delta = q[m.wheels()[i].contact_dof] + run.unevennessUnderWheels()[i];
      if (delta > 0.0) e += 0.4 * C * delta * delta * std::sqrt(delta);
    }
    return e;
  };
  PassageBlock b;
  run.advance(1, b);
  const double e0 = energy();
  std::vector<double> F = run.contactForces(), z = run.unevennessUnderWheels();
  double work = 0.0, worst = 0.0, exchanged = 0.0;
  while (!run.finished()) {
    run.advance(1, b);
    for (int i = 0; i < m.wheelCount(); ++i)
      work += 0.5 * (F[i] + run.contactForces()[i]) * (run.unevennessUnderWheels()[i] - z[i]);
    F = run.contactForces();
    z = run.unevennessUnderWheels();
    worst = std::max(worst, std::abs(energy() - e0 - work));
    exchanged = std::max(exchanged, std::abs(work));
  }
  std::printf("[ figures  ] undamped, rigid, resilient trailer wheels: work %.4g J, worst |E - E0 - W| %.3g J (%.3g)\n",
              exchanged, worst, worst / exchanged);
  EXPECT_GT(exchanged, 1.0);
  EXPECT_LT(worst, 1e-3 * exchanged);
}

}  // namespace
