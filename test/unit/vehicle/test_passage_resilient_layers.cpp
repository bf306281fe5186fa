// The coupled passage on a track with resilient layers (issue 33): under-sleeper pads and under-ballast
// mats add massless nodes to the implicit track. Held against the work-energy balance of the
// undamped coupled system (the layers' nodes store strain energy only), against boundedness of the
// damped passage over the defect at both widths, and against statics (the foundation forces, with a
// mat the mat's, carry the vehicle's weight).
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
#include "railvib/vehicle/passage.hpp"
#include "vehicle_test_util.hpp"

using namespace railvib;
using namespace railvib::vehicle;
using railvib::vehicle::test::with;

namespace {

struct LayeredRun {
  explicit LayeredRun(const std::vector<std::string>& overrides)
      : cfg(Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml", overrides)),
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

// The front axle over the defect at x = 0 and the ringing after it (as test_passage_full_width).
const std::vector<std::string> kOverDefect = {"simulation.duration_s=0.08", "simulation.front_axle_start_m=-0.3",
                                              "simulation.time_step_s=2.0e-5"};

struct Measure {
  std::string name;
  std::vector<std::string> overrides;
};
const std::vector<Measure> kMeasures = {{"usp", {"track.under_sleeper_pad.enabled=true"}},
                                        {"ubm", {"track.under_ballast_mat.enabled=true"}}};

// Damped (the paper's track and the layers' loss factors): over the defect the coupled system stays
// bounded at both widths on the CLM, and the track's energy rings down after the impact; at the start
// (static equilibrium) the forces on the foundation carry the wheels' loads.
TEST(ResilientLayerPassage, PassageOverTheDefectStaysBoundedAtBothWidths) {
  for (const Measure& m : kMeasures) {
    for (const std::string width : {"half", "full"}) {
      LayeredRun s(with(with(kOverDefect, m.overrides), {"track.width=" + width}));
      ASSERT_TRUE(s.tp.under_sleeper_pad.has_value() || s.tp.under_ballast_mat.has_value());
      VehiclePassage run(s.model, s.unevenness, s.pp, makeRailSupport(s.pp, s.tp), PassageOptions{true, true});
      const track::TrackNewmark& trk = dynamic_cast<FlexibleRail&>(run.rail()).integrator();
      PassageBlock b;
      run.advance(1, b);
      // statics: the forces on the foundation (every sleeper, every rail seat) = the contact forces
      double contact = 0.0, foundation = 0.0;
      for (double f : run.contactForces()) contact += f;
      for (double f : b.ballast_force_n) foundation += f;
      EXPECT_NEAR(foundation / contact, 1.0, 1e-3) << m.name << " " << width;
      const double e0 = trk.totalEnergy();
      double peak = e0, late_peak = 0.0, peak_force = 0.0;
      const double static_force = *std::max_element(run.contactForces().begin(), run.contactForces().end());
      size_t steps = 0;
      const size_t total = static_cast<size_t>(run.totalSamples());
      while (!run.finished()) {
        run.advance(1, b);
        ++steps;
        const double e = trk.totalEnergy();
        ASSERT_TRUE(std::isfinite(e)) << m.name << " " << width;
        peak = std::max(peak, e);
        if (steps > 3 * total / 4) late_peak = std::max(late_peak, e);
        for (double f : run.contactForces()) peak_force = std::max(peak_force, f);
      }
      std::printf(
          "[ figures  ] %s, %s width: track energy static %.4g J, peak %.4g J, last quarter peak %.4g J; "
          "peak contact force %.4g N (static %.4g N)\n",
          m.name.c_str(), width.c_str(), e0, peak, late_peak, peak_force, static_force);
      // The impact on the 1 mm defect raises the contact force a few times the static load; an unstable
      // scheme grows without bound. Bounds: 3 x the static track energy, 10 x the static wheel load.
      EXPECT_LT(peak, 3.0 * e0) << m.name << " " << width;
      EXPECT_LT(peak_force, 10.0 * static_force) << m.name << " " << width;
      EXPECT_LT(late_peak, peak) << m.name << " " << width;  // rings down after the impact
    }
  }
}

// Undamped vehicle and track (layers with loss factor 0), half width, CLM, both layers: the coupled
// system's energy changes by the work of the contact forces on the defect's profile (and on the
// rail's displacement under the moving points), as test_passage_full_width's balance.
TEST(ResilientLayerPassage, UndampedCoupledSystemWorkEnergyBalanceWithBothLayers) {
  const std::string t = "vehicles.t2000.suspension_stages.";
  LayeredRun s(with(
      kOverDefect,
      {"simulation.time_step_s=1.0e-5", "simulation.contact_tolerance=1.0e-12", t + "secondary.damping_n_s_m=0",
       t + "motor_primary.damping_n_s_m=0", t + "trailer_primary.damping_n_s_m=0", t + "resilient_ring.damping_n_s_m=0",
       "track.ends.absorbing_length_m=0", "track.railpad.damping_n_s_m=0", "track.ballast.damping_n_s_m=0",
       "track.foundation.clm.damping_n_s_m=0", "track.foundation.clm.coupling_damping_n_s_m=0",
       "track.under_sleeper_pad.enabled=true", "track.under_sleeper_pad.loss_factor=0",
       "track.under_ballast_mat.enabled=true", "track.under_ballast_mat.loss_factor=0"}));
  const VehicleModel& m = s.model;
  ASSERT_EQ(m.damping().norm(), 0.0);
  VehiclePassage run(m, s.unevenness, s.pp, makeRailSupport(s.pp, s.tp));
  const track::TrackNewmark& track = dynamic_cast<FlexibleRail&>(run.rail()).integrator();
  ASSERT_EQ(track.model().damping().norm(), 0.0);
  ASSERT_GE(track.model().padDof(0), 0);
  ASSERT_GE(track.model().matDof(0), 0);
  const passage_test::WorkEnergyBalance balance = passage_test::coupledWorkEnergyBalance(run, m);
  const double exchanged = balance.exchanged_j, worst = balance.worst_j;
  std::printf("[ figures  ] undamped coupled CLM with USP + UBM: work %.4g J, worst |E - E0 - W| %.3g J (%.3g)\n",
              exchanged, worst, worst / exchanged);
  EXPECT_GT(exchanged, 1.0);
  EXPECT_LT(worst, 1e-3 * exchanged);
}

}  // namespace
