// The full-width track (track.width: full): both rails on whole sleepers with heave and roll, a
// railpad, ballast and foundation chain under each rail seat. Held against the half track it
// generalises: in phase it is the half track, in anti-phase the half track whose sleeper weighs
// the roll inertia over 2 a^2, and a static load stays on its rail.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/track/track_newmark.hpp"
#include "test_sampling.hpp"
#include "track_test_util.hpp"

namespace railvib::track {
namespace {

// 1-500 Hz in 3.7 Hz steps (every 4th of them in the sanitizer run: test_sampling.hpp).
std::vector<double> fullWidthFrequencies() {
  std::vector<double> f;
  for (double v = 1.0; v <= 500.0; v += 3.7) f.push_back(v);
  return railvib::test::sampled(f);
}

const char* kFoundations[] = {"clm", "winkler", "rigid"};

// Both rails loaded alike: no roll, each rail carries what the half track carries (the whole sleeper
// weighs two half sleepers), at a sleeper and mid-span, over 1-500 Hz, on every foundation.
TEST(FullWidthTrack, InPhaseLoadingIsTheHalfTrack) {
  for (const std::string fm : kFoundations) {
    const TrackModel half(test::harenScenario({"track.foundation.model=" + fm}));
    const TrackModel full(test::harenScenario({"track.foundation.model=" + fm, "track.width=full"}));
    ASSERT_EQ(full.railCount(), 2);
    for (double x : {0.0, 0.36}) {
      const double err = test::worstRelative(full.receptance(x, fullWidthFrequencies(), RailLoading::Both),
                                             half.receptance(x, fullWidthFrequencies()));
      EXPECT_LT(err, 1e-9) << fm << " at x = " << x;
    }
    // Static: the ballast forces under each seat equal the half track's.
    const Eigen::VectorXd uh = half.staticDeflection({{0.1, 1.0e4}});
    const Eigen::VectorXd uf = full.staticDeflection({{0.1, 1.0e4, Rail::Left}, {0.1, 1.0e4, Rail::Right}});
    const Eigen::VectorXd zh = Eigen::VectorXd::Zero(half.dofCount()), zf = Eigen::VectorXd::Zero(full.dofCount());
    const std::vector<double> fh = half.ballastForceOnFoundation(uh, zh);
    for (Rail r : {Rail::Left, Rail::Right}) {
      const std::vector<double> ff = full.ballastForceOnFoundation(uf, zf, r);
      ASSERT_EQ(ff.size(), fh.size());
      for (size_t i = 0; i < fh.size(); ++i) EXPECT_NEAR(ff[i], fh[i], 1e-9 * 1.0e4) << fm << " sleeper " << i;
    }
  }
}

// Anti-phase: the sleeper rolls about its centre, heave and the other rail's mirror image cancel;
// each seat then carries the roll inertia's share J / (2 a^2) as its sleeper mass. Closed form:
// kinetic energy J phi'^2 / 2 with the seats at +-a moving by +-a phi.
TEST(FullWidthTrack, AntiPhaseIsTheHalfTrackWithTheRollInertiaAsSleeperMass) {
  for (const std::string fm : kFoundations) {
    const TrackParams fp = test::harenScenario({"track.foundation.model=" + fm, "track.width=full"});
    const double a = fp.rail_seat_offset_m;
    EXPECT_DOUBLE_EQ(a, 0.5 * 1.435);  // site.rail_gauge_m / 2
    const double equivalent_kg = fp.sleeper_roll_inertia_kg_m2 / (2.0 * a * a);
    const TrackModel full(fp);
    std::ostringstream mass;
    mass << std::setprecision(17) << equivalent_kg;
    const TrackModel half(test::harenScenario({"track.foundation.model=" + fm, "track.sleeper.mass_kg=" + mass.str()}));
    const auto anti = full.receptance(0.0, fullWidthFrequencies(), RailLoading::AntiPhase);
    EXPECT_LT(test::worstRelative(anti, half.receptance(0.0, fullWidthFrequencies())), 1e-9) << fm;
    // and the two cases really differ (50.7 kg m^2 over 2 a^2 = 49.2 kg against 45 kg per seat)
    EXPECT_GT(test::worstRelative(anti, full.receptance(0.0, fullWidthFrequencies(), RailLoading::Both)), 1e-3) << fm;
  }
}

// The seats are the sleeper's only supports and loads: in seat coordinates (heave +- a roll) the
// stiffness has no term across the track, so a static load on the left rail stays on it. The left
// seats carry the half track's ballast forces (their sum the load: equilibrium), the right ones
// nothing; the rails couple only through the sleeper's mass distribution, dynamically.
TEST(FullWidthTrack, AStaticLoadOnOneRailStaysOnIt) {
  for (const std::string fm : kFoundations) {
    const TrackModel half(test::harenScenario({"track.foundation.model=" + fm}));
    const TrackModel full(test::harenScenario({"track.foundation.model=" + fm, "track.width=full"}));
    const double load_n = 5.0e4;
    const Eigen::VectorXd uf = full.staticDeflection({{0.2, load_n, Rail::Left}});
    const Eigen::VectorXd uh = half.staticDeflection({{0.2, load_n}});
    const Eigen::VectorXd zf = Eigen::VectorXd::Zero(full.dofCount()), zh = Eigen::VectorXd::Zero(half.dofCount());
    const std::vector<double> left = full.ballastForceOnFoundation(uf, zf, Rail::Left);
    const std::vector<double> right = full.ballastForceOnFoundation(uf, zf, Rail::Right);
    const std::vector<double> ref = half.ballastForceOnFoundation(uh, zh);
    double sum_left = 0.0, worst_right = 0.0;
    for (size_t i = 0; i < left.size(); ++i) {
      sum_left += left[i];
      worst_right = std::max(worst_right, std::abs(right[i]));
      EXPECT_NEAR(left[i], ref[i], 1e-9 * load_n) << fm << " sleeper " << i;
    }
    EXPECT_NEAR(sum_left, load_n, 1e-8 * load_n) << fm;
    EXPECT_LT(worst_right, 1e-9 * load_n) << fm;
    EXPECT_NEAR(full.railPoint(0.2, Rail::Right).displacement(uf), 0.0, 1e-15) << fm;
    // dynamically the right rail moves: the sleeper's heave and roll are inertially coupled
    const auto cross = full.receptance(0.0, {80.0}, RailLoading::Left);
    const auto right_of_right = full.receptance(0.0, {80.0}, RailLoading::Right);
    EXPECT_LT(test::worstRelative(right_of_right, cross), 1e-9) << fm;  // mirror image: left = right
  }
}

// No dampers: the average-acceleration Newmark scheme conserves the discrete energy of the
// full-width track (heave, roll and both rails moving) as it does the half track's.
TEST(FullWidthTrack, UndampedEnergyIsConserved) {
  for (const std::string fm : kFoundations) {
    const TrackModel model(test::harenScenario(
        {"track.width=full", "track.foundation.model=" + fm, "track.extent.x_min_m=0", "track.extent.x_max_m=10",
         "track.ends.absorbing_length_m=0", "track.railpad.damping_n_s_m=0", "track.ballast.damping_n_s_m=0",
         "track.foundation.clm.damping_n_s_m=0", "track.foundation.clm.coupling_damping_n_s_m=0",
         "track.foundation.winkler.damping_n_s_m=0"}));
    ASSERT_EQ(model.damping().norm(), 0.0);
    TrackNewmark nm(model, 1.0e-4);
    Eigen::VectorXd v = Eigen::VectorXd::Zero(model.dofCount());
    for (int j = 0; j < model.railNodeCount(); ++j) {
      const double x = model.railNodePositions()[j];
      v[model.railW(j, Rail::Left)] = 0.01 * std::sin(M_PI * x / 10.0);
      v[model.railW(j, Rail::Right)] = -0.004 * std::sin(3.0 * M_PI * x / 10.0);
    }
    for (int i = 0; i < model.sleeperCount(); ++i) v[model.sleeperRollDof(i)] = 0.002 * (i % 2 ? 1.0 : -1.0);
    nm.setState(Eigen::VectorXd::Zero(model.dofCount()), v, Eigen::VectorXd::Zero(model.dofCount()));
    const double e0 = nm.totalEnergy();
    double worst = 0.0, max_strain = 0.0;
    for (int k = 0; k < 20000; ++k) {
      nm.step({});
      if (k % 10 == 0) {
        worst = std::max(worst, std::abs(nm.totalEnergy() / e0 - 1.0));
        max_strain = std::max(max_strain, nm.strainEnergy());
      }
    }
    EXPECT_LT(worst, 1e-8) << fm;
    EXPECT_GT(max_strain, 0.3 * e0) << fm;
  }
}

TEST(FullWidthTrack, BadWidthsAndRailsAreRefused) {
  try {
    test::harenScenario({"track.width=both"});
    ADD_FAILURE() << "track.width=both accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("track.width"), std::string::npos) << e.what();
  }
  try {  // the rail seats must lie on the sleeper
    test::harenScenario({"track.width=full", "track.sleeper.length_m=1.2"});
    ADD_FAILURE() << "seats off a 1.2 m sleeper accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("track.sleeper.length_m"), std::string::npos) << e.what();
  }
  try {  // no site: no gauge
    loadTrackParams(Config::load(test::configPath("track_haren.yaml"), test::fixedExtent({"track.width=full"})).root());
    ADD_FAILURE() << "full width without a site accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("site.rail_gauge_m"), std::string::npos) << e.what();
  }
  const TrackModel half(test::harenScenario({}));
  EXPECT_THROW(half.railPoint(0.0, Rail::Right), std::invalid_argument);
  EXPECT_THROW(half.receptance(0.0, {10.0}, RailLoading::AntiPhase), std::invalid_argument);
}

}  // namespace
}  // namespace railvib::track
