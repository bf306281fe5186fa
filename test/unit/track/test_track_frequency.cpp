// Frequency-domain acceptance: discrete track vs the continuous beam, statics, k_b sweep.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

#include "railvib/track/dynamic_stiffness_lu.hpp"
#include "railvib/track/track_analysis.hpp"
#include "track_test_util.hpp"

namespace railvib::track {
namespace {

// Discrete supports (pad - sleeper - ballast on a rigid base) vs the analytic
// continuous beam on the smeared 2-layer support, 5 Hz .. f_pp / 2, at a
// sleeper and at midspan.
TEST(TrackReceptance, ConvergesToContinuousBeamOnTwoLayerSupport) {
  const TrackParams p = test::haren({"track.foundation.model=rigid"});
  const TrackModel model(p);
  const double fpp = pinnedPinnedFrequency(p);
  EXPECT_NEAR(fpp, 842.0, 2.0);
  const std::vector<double> f = test::logGrid(5.0, 0.5 * fpp, 60);
  for (double x : {0.0, 0.5 * p.layout.spacing_m}) {
    const auto r = model.receptance(x, f);
    double worst = 0.0, worst_f = 0.0;
    for (size_t i = 0; i < f.size(); ++i) {
      const double err = std::abs(std::abs(r[i]) / std::abs(continuousBeamReceptance(p, f[i])) - 1.0);
      if (err > worst) {
        worst = err;
        worst_f = f[i];
      }
    }
    RecordProperty(x == 0.0 ? "max_error_at_sleeper" : "max_error_at_midspan", std::to_string(worst));
    std::cout << "receptance vs continuous beam, x = " << x << " m: max |error| " << 100.0 * worst << " % at "
              << worst_f << " Hz\n";
    EXPECT_LT(worst, 0.05) << "at x = " << x << " m, worst at " << worst_f << " Hz";
  }
  // The phase lags (Im < 0) like the analytic receptance (e^{iwt} convention).
  EXPECT_LT(model.receptance(0.0, 100.0).imag(), 0.0);
  EXPECT_LT(continuousBeamReceptance(p, 100.0).imag(), 0.0);
  // Above f_pp the discrete track departs from the continuous one (pinned-pinned
  // resonance/antiresonance): the comparison is discriminating.
  const double above = std::abs(model.receptance(0.5 * p.layout.spacing_m, fpp * 1.03)) /
                       std::abs(continuousBeamReceptance(p, fpp * 1.03));
  EXPECT_GT(above, 1.2);
}

TEST(TrackStatics, PointLoadMatchesWinklerBeam) {
  const double F = 50.0e3;
  for (const std::string model_name : {"rigid", "winkler"}) {
    const TrackParams p = test::haren({"track.foundation.model=" + model_name});
    const TrackModel model(p);
    const double w_ref =
        winklerBeamStaticDeflection(p.rail_bending_stiffness_n_m2, smearedStaticSupportStiffness(p), F);
    for (double x : {0.0, 0.5 * p.layout.spacing_m, 0.25 * p.layout.spacing_m}) {
      const Eigen::VectorXd u = model.staticDeflection({{x, F}});
      const double w = model.railPoint(x).displacement(u);
      std::cout << "static " << model_name << " x = " << x << ": w = " << w << " m, Winkler beam " << w_ref
                << " m, error " << 100.0 * (w / w_ref - 1.0) << " %\n";
      EXPECT_NEAR(w / w_ref, 1.0, 0.02) << model_name << " at x = " << x;
      EXPECT_GT(w, 0.0);  // positive downward
      // Statics: the ballast carries the whole load.
      double sum = 0.0;
      for (double b : model.ballastForceOnFoundation(u, Eigen::VectorXd::Zero(u.size()))) sum += b;
      EXPECT_NEAR(sum / F, 1.0, 1e-9);
    }
  }
}

// Resonances of the paper's receptance study (Fig 4): the out-of-phase
// rail/ballast mode rises with k_b (roughly as sqrt(k_b) for the part of the
// stiffness it controls) and depends much less on k_f; the CLM in-phase mode
// (~15 Hz, foundation mass bounce) moves up slightly with k_b.
struct Peaks {
  std::vector<ReceptancePeak> peaks;
};

Peaks peaksOf(const TrackParams& p) {
  std::vector<double> f;
  for (double x = 4.0; x <= 200.0; x += 1.0) f.push_back(x);
  const TrackModel model(p);
  return {findPeaks(f, model.receptance(0.0, f))};
}

TEST(TrackReceptance, BallastStiffnessShiftsResonances) {
  // --- CLM: two peaks (in-phase ~15 Hz, out-of-phase ~78 Hz)
  const TrackParams clm =
      test::haren({"track.foundation.model=clm", "track.extent.mode=fixed", "track.extent.x_min_m=-30",
                   "track.extent.x_max_m=30", "track.ends.absorbing_length_m=10"});
  auto with_kb = [](TrackParams p, double factor) {
    p.ballast_stiffness_n_m *= factor;  // k_f fixed (Winkler k_f was derived from the nominal k_b)
    return p;
  };
  auto with_kf = [](TrackParams p, double factor) {
    p.clm.stiffness_n_m *= factor;
    p.winkler.stiffness_n_m *= factor;
    return p;
  };
  const Peaks c1 = peaksOf(clm), c2 = peaksOf(with_kb(clm, 2.0)), cf = peaksOf(with_kf(clm, 2.0));
  ASSERT_EQ(c1.peaks.size(), 2u);
  ASSERT_EQ(c2.peaks.size(), 2u);
  ASSERT_EQ(cf.peaks.size(), 2u);
  std::cout << "CLM peaks: nominal " << c1.peaks[0].frequency_hz << ", " << c1.peaks[1].frequency_hz << " Hz; 2 k_b "
            << c2.peaks[0].frequency_hz << ", " << c2.peaks[1].frequency_hz << " Hz; 2 k_f " << cf.peaks[0].frequency_hz
            << ", " << cf.peaks[1].frequency_hz << " Hz\n";
  EXPECT_NEAR(c1.peaks[0].frequency_hz, 15.0, 3.0);
  EXPECT_NEAR(c1.peaks[1].frequency_hz, 75.0, 10.0);
  const double r_out = c2.peaks[1].frequency_hz / c1.peaks[1].frequency_hz;
  EXPECT_GT(r_out, 1.3);
  EXPECT_LT(r_out, 1.7);
  const double r_in = c2.peaks[0].frequency_hz / c1.peaks[0].frequency_hz;
  EXPECT_GE(r_in, 1.0);
  EXPECT_LT(r_in, 1.05);
  // k_f barely moves the out-of-phase mode
  EXPECT_LT(std::abs(cf.peaks[1].frequency_hz / c1.peaks[1].frequency_hz - 1.0), 0.05);

  // --- Winkler: the track resonance (~70 Hz [paper]) rises with k_b, much less with k_f
  const TrackParams wk =
      test::haren({"track.foundation.model=winkler", "track.extent.mode=fixed", "track.extent.x_min_m=-30",
                   "track.extent.x_max_m=30", "track.ends.absorbing_length_m=10"});
  const Peaks w1 = peaksOf(wk), w2 = peaksOf(with_kb(wk, 2.0)), wf = peaksOf(with_kf(wk, 2.0));
  const Peaks wh = peaksOf(with_kb(wk, 0.5));
  ASSERT_EQ(w1.peaks.size(), 1u);
  ASSERT_EQ(w2.peaks.size(), 1u);
  ASSERT_EQ(wf.peaks.size(), 1u);
  ASSERT_EQ(wh.peaks.size(), 1u);
  std::cout << "Winkler peak: nominal " << w1.peaks[0].frequency_hz << " Hz; k_b/2 " << wh.peaks[0].frequency_hz
            << " Hz; 2 k_b " << w2.peaks[0].frequency_hz << " Hz; 2 k_f " << wf.peaks[0].frequency_hz << " Hz\n";
  EXPECT_NEAR(w1.peaks[0].frequency_hz, 70.0, 8.0);
  const double rw = w2.peaks[0].frequency_hz / w1.peaks[0].frequency_hz;
  EXPECT_GT(rw, 1.2);
  EXPECT_LT(rw, 1.6);
  EXPECT_LT(wh.peaks[0].frequency_hz, 0.7 * w1.peaks[0].frequency_hz);
  const double rwf = wf.peaks[0].frequency_hz / w1.peaks[0].frequency_hz;
  EXPECT_GT(rwf, 1.0);
  EXPECT_LT(rwf - 1.0, 0.5 * (rw - 1.0));  // k_f matters less than k_b
}

// The sweep's factorisation on a chain of n masses m, each tied to the next and to ground by a spring k
// with a dashpot c: at each frequency the solve matches the dense LU of the same D(w) to round-off, and
// for n = 1 the analytic receptance 1 / (k - w^2 m + i w c). A singular D and a changed pattern are refused.
TEST(TrackReceptance, DynamicStiffnessLuSolvesADampedChain) {
  using Cplx = std::complex<double>;
  const double m = 50.0, k = 2.0e7, c = 4.0e3;  // kg, N/m, N s/m
  const auto chain = [&](int n, double w) {
    std::vector<Eigen::Triplet<Cplx>> t;
    const Cplx spring(k, w * c);
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, i, spring - w * w * m);  // to ground, and the mass
      if (i + 1 < n) {
        t.emplace_back(i, i, spring);
        t.emplace_back(i + 1, i + 1, spring);
        t.emplace_back(i, i + 1, -spring);
        t.emplace_back(i + 1, i, -spring);
      }
    }
    DynamicStiffnessLu::Matrix d(n, n);
    d.setFromTriplets(t.begin(), t.end());
    return d;
  };
  DynamicStiffnessLu one;
  for (double f : {1.0, 100.0, 1000.0}) {
    const double w = 2.0 * M_PI * f;
    one.factorize(chain(1, w), "test");
    const Cplx x = one.solve(Eigen::VectorXcd(Eigen::VectorXcd::Ones(1)))[0];
    EXPECT_LT(std::abs(x * Cplx(k - w * w * m, w * c) - 1.0), 1e-12) << f << " Hz";
  }
  const int n = 40;
  DynamicStiffnessLu lu;
  Eigen::MatrixXcd b = Eigen::MatrixXcd::Zero(n, 2);
  b(0, 0) = 1.0;
  b(n / 2, 1) = Cplx(0.0, 1.0);
  for (double f : {5.0, 120.0, 700.0, 2500.0}) {
    const DynamicStiffnessLu::Matrix d = chain(n, 2.0 * M_PI * f);
    lu.factorize(d, "test");
    const Eigen::MatrixXcd x = lu.solve(b);
    const Eigen::MatrixXcd dense = Eigen::MatrixXcd(d).partialPivLu().solve(b);
    EXPECT_LT((x - dense).norm() / dense.norm(), 1e-12) << f << " Hz";
    EXPECT_LT((lu.solve(Eigen::VectorXcd(b.col(1))) - dense.col(1)).norm() / dense.col(1).norm(), 1e-12);
  }
  try {
    lu.factorize(chain(n - 1, 10.0), "test sweep");
    ADD_FAILURE() << "a changed pattern was factorised";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("test sweep: the dynamic stiffness changed its sparsity pattern"),
              std::string::npos)
        << e.what();
  }
  DynamicStiffnessLu singular;
  DynamicStiffnessLu::Matrix rank_one(2, 2);
  std::vector<Eigen::Triplet<Cplx>> ones{{0, 0, 1.0}, {0, 1, 1.0}, {1, 0, 1.0}, {1, 1, 1.0}};
  rank_one.setFromTriplets(ones.begin(), ones.end());
  try {
    singular.factorize(rank_one, "rank one");
    ADD_FAILURE() << "a singular matrix was factorised";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("rank one: factorisation failed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(singular.solve(Eigen::VectorXcd(Eigen::VectorXcd::Ones(2))), std::logic_error);
}

}  // namespace
}  // namespace railvib::track
