// Time-domain acceptance: Newmark energy, quasi-static equilibrium, end
// reflections, the coupling API.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "railvib/track/soil_load_stream.hpp"
#include "railvib/track/track_analysis.hpp"
#include "railvib/track/track_newmark.hpp"
#include "railvib/track/track_stepper.hpp"
#include "track_test_util.hpp"

namespace railvib::track {
namespace {

// All dampers zero, no load, non-zero initial state: the average-acceleration
// Newmark scheme conserves 1/2 v'Mv + 1/2 u'Ku exactly (up to round-off).
TEST(TrackNewmarkEnergy, ConservedWithoutDamping) {
  for (const std::string fm : {"clm", "winkler", "rigid"}) {
    const TrackParams p =
        test::haren({"track.foundation.model=" + fm, "track.extent.mode=fixed", "track.extent.x_min_m=0",
                     "track.extent.x_max_m=10", "track.ends.absorbing_length_m=0", "track.railpad.damping_n_s_m=0",
                     "track.ballast.damping_n_s_m=0", "track.foundation.clm.damping_n_s_m=0",
                     "track.foundation.clm.coupling_damping_n_s_m=0", "track.foundation.winkler.damping_n_s_m=0"});
    const TrackModel model(p);
    ASSERT_EQ(model.damping().norm(), 0.0);
    TrackNewmark nm(model, 1.0e-4);
    const Eigen::Index n = model.dofCount();
    // Initial velocity: a smooth bump of the rail and the sleepers (u = 0, a = 0 is consistent).
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
    for (int j = 0; j < model.railNodeCount(); ++j) {
      const double x = model.railNodePositions()[j];
      v[model.railW(j)] = 0.01 * std::sin(M_PI * x / 10.0) + 0.003 * std::sin(7.0 * M_PI * x / 10.0);
    }
    for (int i = 0; i < model.sleeperCount(); ++i) v[model.sleeperDof(i)] = -0.005 * (i % 3);
    nm.setState(Eigen::VectorXd::Zero(n), v, Eigen::VectorXd::Zero(n));
    const double e0 = nm.totalEnergy();
    ASSERT_GT(e0, 0.0);
    double worst = 0.0, max_strain = 0.0;
    const std::vector<PointLoad> none;
    for (int k = 0; k < 100000; ++k) {
      nm.step(none);
      if (k % 10 == 0) {
        worst = std::max(worst, std::abs(nm.totalEnergy() / e0 - 1.0));
        max_strain = std::max(max_strain, nm.strainEnergy());
      }
    }
    worst = std::max(worst, std::abs(nm.totalEnergy() / e0 - 1.0));
    std::cout << fm << ": relative energy drift over 1e5 steps " << worst << "\n";
    EXPECT_LT(worst, 1e-8) << fm;
    EXPECT_GT(max_strain, 0.3 * e0);  // energy really sloshes between kinetic and strain
  }
}

// With damping the energy can only decrease (C positive semi-definite, incl. negative d_c).
TEST(TrackNewmarkEnergy, DecaysWithDamping) {
  const TrackParams p = test::haren({"track.extent.mode=fixed", "track.extent.x_min_m=0", "track.extent.x_max_m=10",
                                     "track.ends.absorbing_length_m=0"});
  const TrackModel model(p);
  EXPECT_TRUE(model.dampingIsPositiveSemiDefinite());
  TrackNewmark nm(model, 1.0e-4);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.dofCount());
  for (int i = 0; i < model.sleeperCount(); ++i) v[model.baseDof(i)] = (i % 2 ? 0.01 : -0.01);
  nm.setState(Eigen::VectorXd::Zero(model.dofCount()), v, Eigen::VectorXd::Zero(model.dofCount()));
  double prev = nm.totalEnergy();
  for (int k = 0; k < 2000; ++k) {
    nm.step({});
    EXPECT_LE(nm.totalEnergy(), prev * (1.0 + 1e-12));
    prev = nm.totalEnergy();
  }
  EXPECT_LT(prev, 0.01 * (0.5 * v.dot(model.mass() * v)));
}

// Constant loads moving slowly: the ballast-to-soil loads sum to the applied loads.
TEST(TrackMovingLoad, QuasiStaticEquilibrium) {
  for (const std::string fm : {"clm", "winkler"}) {
    const TrackModel model(test::haren({"track.foundation.model=" + fm}));
    MovingLoadRun run;
    run.dt_s = 1.0e-3;
    run.duration_s = 6.0;
    run.front_start_m = 10.0;
    run.speed_m_s = 2.0;
    run.offsets_behind_m = {0.0, 1.6667, 7.5, 9.1667, 15.0, 16.6667};
    run.forces_n = {26.0e3, 25.0e3, 27.0e3, 26.5e3, 24.0e3, 26.0e3};
    const double applied = std::accumulate(run.forces_n.begin(), run.forces_n.end(), 0.0);
    double worst = 0.0, worst_all = 0.0;
    simulateMovingLoads(model, run, [&](double t, const std::vector<double>& b) {
      const double err = std::abs(std::accumulate(b.begin(), b.end(), 0.0) / applied - 1.0);
      worst_all = std::max(worst_all, err);
      if (t >= 1.0) worst = std::max(worst, err);
    });
    std::cout << fm << ": max |sum ballast / sum loads - 1| after 1 s: " << worst << " (whole run " << worst_all
              << ")\n";
    EXPECT_LT(worst, 0.005) << fm;
  }
}

// Coupling API: predict + unit responses + commitContact == step with the same loads.
TEST(TrackNewmarkCoupling, ContactStepEqualsPlainStep) {
  const TrackModel model(test::haren({"track.extent.mode=fixed", "track.extent.x_min_m=-15", "track.extent.x_max_m=15",
                                      "track.ends.absorbing_length_m=4"}));
  TrackNewmark a(model, 1.0e-5), b(model, 1.0e-5);
  const std::vector<PointLoad> initial{{-1.0, 20e3}, {0.7, 30e3}};
  a.setStaticEquilibrium(initial);
  b.setStaticEquilibrium(initial);
  for (int k = 0; k < 50; ++k) {
    const std::vector<double> xs{-1.0 + 0.013 * k, 0.7 + 0.013 * k};
    const std::vector<double> fs{20e3 + 1e3 * std::sin(0.3 * k), 30e3 + 5e3 * std::cos(0.2 * k)};
    a.predict();
    std::vector<RailPoint> pts{model.railPoint(xs[0]), model.railPoint(xs[1])};
    a.setContactPoints(pts);
    const Eigen::MatrixXd G = a.contactCompliance();
    EXPECT_NEAR(G(0, 1), G(1, 0), 1e-12 * G(0, 0));
    EXPECT_GT(G(0, 0), 0.0);
    EXPECT_NEAR(a.compliance(pts[0], pts[1]), G(0, 1), 1e-12 * G(0, 0));
    const Eigen::Vector2d predicted = a.contactFreeDisplacements() + G * Eigen::Vector2d(fs[0], fs[1]);
    a.commitContact(fs);
    b.step({{xs[0], fs[0]}, {xs[1], fs[1]}});
    EXPECT_NEAR(a.railDisplacement(xs[0]), predicted[0], 1e-12);
    EXPECT_NEAR(a.railDisplacement(xs[1]), predicted[1], 1e-12);
    EXPECT_LT((a.displacement() - b.displacement()).norm(), 1e-10 * b.displacement().norm());
    EXPECT_LT((a.velocity() - b.velocity()).norm(), 1e-8 * (b.velocity().norm() + 1e-9));
  }
  // commit(point loads) is the same again
  a.predict();
  b.predict();
  a.commit({{0.3, 10e3}});
  b.setContactPoints({model.railPoint(0.3)});
  b.commitContact({10e3});
  EXPECT_LT((a.displacement() - b.displacement()).norm(), 1e-10 * b.displacement().norm());
}

// End treatment: the response to an impulse 2 m inside the zone of interest
// (2 m before the damping layer) matches that of a much longer track; without
// the layer it does not.
double impulseMismatch(const std::string& ends_length, const std::vector<std::string>& overrides) {
  auto run = [&](double half_length, const std::string& labs) {
    std::vector<std::string> o = overrides;
    o.push_back("track.extent.mode=fixed");
    o.push_back("track.extent.x_min_m=-50");
    o.push_back("track.extent.x_max_m=" + std::to_string(half_length));
    o.push_back("track.ends.absorbing_length_m=" + labs);
    const TrackModel model(test::haren(o));
    TrackNewmark nm(model, 1.0e-4);
    const double x_load = 50.0 - 12.0 - 2.0;  // 2 m before the layer of the short track
    std::vector<double> w, fb;
    // ballast force of the sleeper under the load
    int s_load = 0;
    for (int i = 0; i < model.sleeperCount(); ++i) {
      if (std::abs(model.sleeperPositions()[i] - x_load) < std::abs(model.sleeperPositions()[s_load] - x_load)) {
        s_load = i;
      }
    }
    std::vector<double> ballast;
    for (int k = 1; k <= 4000; ++k) {
      const double t = k * 1.0e-4;
      const double f = t < 0.002 ? 50.0e3 * std::sin(M_PI * t / 0.002) : 0.0;
      nm.step({{x_load, f}});
      w.push_back(nm.railDisplacement(x_load));
      nm.ballastForces(ballast);
      fb.push_back(ballast[s_load]);
    }
    w.insert(w.end(), fb.begin(), fb.end());
    return w;
  };
  const std::vector<double> ref = run(200.0, "12");
  const std::vector<double> test = run(50.0, ends_length);
  // Compare the late part of each history (after the direct response, t > 0.02 s)
  // relative to the peak: reflections show up there.
  double peak_w = 0.0, peak_f = 0.0, err_w = 0.0, err_f = 0.0;
  const size_t n = ref.size() / 2;
  for (size_t i = 0; i < n; ++i) {
    peak_w = std::max(peak_w, std::abs(ref[i]));
    peak_f = std::max(peak_f, std::abs(ref[n + i]));
  }
  for (size_t i = 0; i < n; ++i) {
    err_w = std::max(err_w, std::abs(test[i] - ref[i]));
    err_f = std::max(err_f, std::abs(test[n + i] - ref[n + i]));
  }
  return std::max(err_w / peak_w, err_f / peak_f);
}

TEST(TrackEnds, ReflectionsAreSmall) {
  for (const std::string fm : {"clm", "winkler"}) {
    // Paper damping: waves decay fast along the track; the layer changes nothing noticeable.
    const std::vector<std::string> paper{"track.foundation.model=" + fm};
    const double with_layer = impulseMismatch("12", paper);
    const double without = impulseMismatch("0", paper);
    std::cout << fm << " (paper damping): max impulse-response difference vs a longer track, relative to peak: "
              << "with end layer " << 100.0 * with_layer << " %, free ends " << 100.0 * without << " %\n";
    EXPECT_LT(with_layer, 0.01) << fm;
    // Stress case: track dampers at 2 % of the paper's values, waves reach the ends.
    const std::vector<std::string> light{"track.foundation.model=" + fm,
                                         "track.railpad.damping_n_s_m=600",
                                         "track.ballast.damping_n_s_m=1040",
                                         "track.foundation.clm.damping_n_s_m=3000",
                                         "track.foundation.clm.coupling_damping_n_s_m=-460",
                                         "track.foundation.winkler.damping_n_s_m=3000"};
    const double light_with = impulseMismatch("12", light);
    const double light_without = impulseMismatch("0", light);
    std::cout << fm << " (2 % damping): with end layer " << 100.0 * light_with << " %, free ends "
              << 100.0 * light_without << " %\n";
    EXPECT_LT(light_with, 0.02) << fm;
    EXPECT_GT(light_without, 3.0 * light_with) << fm;
  }
}

TEST(TrackStepper, SoilLoadsAreTwiceTheHalfTrack) {
  TrackStepper st(test::haren({"track.extent.mode=fixed", "track.extent.x_min_m=-15", "track.extent.x_max_m=15",
                               "track.ends.absorbing_length_m=4"}),
                  1.0e-4);
  st.start({{0.0, 30e3}});
  double sum = 0.0;
  for (size_t i = 0; i < st.soilLoads().size(); ++i) {
    EXPECT_DOUBLE_EQ(st.soilLoads()[i], 2.0 * st.ballastForcesPerSeat()[i]);
    sum += st.soilLoads()[i];
  }
  EXPECT_NEAR(sum, 60e3, 1e-6 * 60e3);
  st.step({{0.001, 30e3}, {1000.0, 1.0}});
  EXPECT_EQ(st.ignoredLoadCount(), 1);
  EXPECT_EQ(st.stepCount(), 1);
  EXPECT_NEAR(st.time(), 1.0e-4, 1e-15);
}

}  // namespace
}  // namespace railvib::track

namespace railvib::track {
namespace {

// The stream the track node wraps: constant loads in, decimated soil loads
// (both rails) out; in statics they sum to twice the applied wheel loads.
TEST(TrackSoilLoadStream, DecimatedLoadsCarryTheAppliedLoad) {
  const TrackParams p = test::haren({"track.extent.mode=fixed", "track.extent.x_min_m=-15", "track.extent.x_max_m=15",
                                     "track.ends.absorbing_length_m=4"});
  SoilLoadStream stream(p, 1.0e-4, 1000.0);
  EXPECT_DOUBLE_EQ(stream.loadSamplePeriod(), 1.0e-3);
  const size_t wheels = 2, samples = 3000;
  std::vector<double> x(samples * wheels), f(samples * wheels), out;
  for (size_t s = 0; s < samples; ++s) {
    x[s * wheels] = -2.0 + 1.0e-4 * s;  // 1 m/s
    x[s * wheels + 1] = 1.0 + 1.0e-4 * s;
    f[s * wheels] = 20e3;
    f[s * wheels + 1] = 30e3;
  }
  size_t frames = stream.push(samples, {Rail::Left, Rail::Left}, x.data(), f.data(), out);
  frames += stream.flush(out);
  const size_t ns = static_cast<size_t>(stream.sleeperCount());
  ASSERT_EQ(out.size(), frames * ns);
  EXPECT_NEAR(static_cast<double>(frames), 300.0, 1.0);
  for (size_t k = 0; k < frames; ++k) {
    double sum = 0.0;
    for (size_t i = 0; i < ns; ++i) sum += out[k * ns + i];
    EXPECT_NEAR(sum / 100e3, 1.0, 1e-3) << "frame " << k;
  }
  EXPECT_NEAR(stream.time(), 1.0e-4 * (samples - 1), 1e-12);
}

// Full width: each rail seat's force, [sleeper][seat]. The same wheels on both rails are the half
// track (each seat carries half of what the half track gives the soil) to round-off; on the left
// rail alone the frames carry the applied load once (statics), most of it on the left seats.
TEST(TrackSoilLoadStream, FullWidthGivesEachRailSeatsForce) {
  const std::vector<std::string> base{"track.extent.mode=fixed", "track.extent.x_min_m=-15", "track.extent.x_max_m=15",
                                      "track.ends.absorbing_length_m=4"};
  std::vector<std::string> full_overrides = base;
  full_overrides.push_back("track.width=full");
  const TrackParams half_params = test::harenScenario(base), full_params = test::harenScenario(full_overrides);
  const size_t samples = 2000;
  auto run = [&](const TrackParams& p, const std::vector<Rail>& rails, std::vector<double>& out) {
    SoilLoadStream stream(p, 1.0e-4, 1000.0);
    const size_t wheels = rails.size();
    std::vector<double> x(samples * wheels), f(samples * wheels);
    for (size_t s = 0; s < samples; ++s) {
      for (size_t w = 0; w < wheels; ++w) {
        const bool second_axle = w >= (wheels + 1) / 2 && wheels > 1;
        x[s * wheels + w] = (second_axle ? 1.0 : -2.0) + 1.0e-4 * s;  // 1 m/s
        f[s * wheels + w] = (second_axle ? 30e3 : 20e3) * (1.0 + 0.3 * std::sin(60.0 * 1e-4 * s));
      }
    }
    size_t frames = stream.push(samples, rails, x.data(), f.data(), out);
    frames += stream.flush(out);
    EXPECT_EQ(out.size(), frames * stream.soilLoadsPerFrame());
    return stream.soilLoadsPerSleeper();
  };
  std::vector<double> half, both, left;
  ASSERT_EQ(run(half_params, {Rail::Left, Rail::Left}, half), 1);
  // two axles on both rails (axle-major: left, right)
  ASSERT_EQ(run(full_params, {Rail::Left, Rail::Right, Rail::Left, Rail::Right}, both), 2);
  ASSERT_EQ(both.size(), 2 * half.size());
  double peak = 0.0, worst = 0.0;
  for (size_t i = 0; i < half.size(); ++i) {
    peak = std::max(peak, std::abs(half[i]));
    for (size_t seat = 0; seat < 2; ++seat) worst = std::max(worst, std::abs(both[2 * i + seat] - 0.5 * half[i]));
  }
  RecordProperty("symmetric_full_vs_half_rel", std::to_string(worst / peak));
  EXPECT_LT(worst, 1e-9 * peak);

  // the left rail alone, constant loads: statics
  SoilLoadStream stream(full_params, 1.0e-4, 1000.0);
  std::vector<double> x{-2.0, 1.0}, f{20e3, 30e3};
  size_t frames = 0;
  for (size_t s = 0; s < samples; ++s) {
    x[0] = -2.0 + 1.0e-4 * s;
    x[1] = 1.0 + 1.0e-4 * s;
    frames += stream.push(1, {Rail::Left, Rail::Left}, x.data(), f.data(), left);
  }
  const size_t ns = static_cast<size_t>(stream.sleeperCount());
  ASSERT_EQ(left.size(), frames * 2 * ns);
  for (size_t k = 0; k < frames; k += 20) {
    double seat_sum[2] = {0.0, 0.0};
    for (size_t i = 0; i < ns; ++i)
      for (size_t seat = 0; seat < 2; ++seat) seat_sum[seat] += left[(k * ns + i) * 2 + seat];
    EXPECT_NEAR((seat_sum[0] + seat_sum[1]) / 50e3, 1.0, 1e-3) << "frame " << k;
    EXPECT_GT(seat_sum[0], 0.5 * 50e3) << "frame " << k;  // the loaded rail's seats carry most of it
  }
}

}  // namespace
}  // namespace railvib::track
