// The rail on a ground given in the frequency domain (track::receptanceOnGround, the seam through
// which the FE soil carries the track: coupling/track_on_soil.hpp). Held against the foundations the
// track model assembles itself: the ground that is their foundation's compliance must give their
// receptance to round-off.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "railvib/track/track_analysis.hpp"
#include "railvib/track/track_model.hpp"
#include "track_test_util.hpp"

namespace railvib::track {
namespace {

using Cplx = std::complex<double>;

std::vector<double> onGroundFrequencies() {
  std::vector<double> f;
  for (double v = 0.5; v <= 300.0; v += 8.3) f.push_back(v);
  return f;
}

TrackParams withFoundation(TrackParams p, FoundationModel m) {
  p.foundation = m;
  return p;
}

// The same damping layer the model puts on a foundation mass at x (TrackModel::build's eta(x)).
double endDampingRate(const TrackModel& m, double x) {
  const EndParams& e = m.params().ends;
  if (e.absorbing_length_m <= 0.0 || e.max_damping_rate_1_s <= 0.0) return 0.0;
  const double depth =
      std::max({0.0, (m.railStart() + e.absorbing_length_m) - x, x - (m.railEnd() - e.absorbing_length_m)});
  const double r = std::min(1.0, depth / e.absorbing_length_m);
  return e.max_damping_rate_1_s * r * r;
}

// A Winkler ground: each footprint on its own spring and damper, G = diag(1 / (k_f + i w d_f)); with
// the resilient layers too (the ground then carries the mat, or the ballast under a pad).
TEST(TrackOnGround, WinklerGroundIsTheWinklerTrack) {
  // the pad's node on the ground's ballast, and the mat on the ground: the two branches of the seam
  const std::vector<std::vector<std::string>> layers = {
      {}, {"track.under_sleeper_pad.enabled=true"}, {"track.under_ballast_mat.enabled=true"}};
  for (const auto& layer : layers) {
    const TrackParams p = test::haren(layer);
    const TrackModel winkler(withFoundation(p, FoundationModel::Winkler));
    const TrackModel rigid(withFoundation(p, FoundationModel::Rigid));
    const Eigen::Index n = rigid.sleeperCount();
    const GroundCompliance ground = [&](double f) {
      const Cplx k(p.winkler.stiffness_n_m, 2.0 * M_PI * f * p.winkler.damping_n_s_m);
      return Eigen::MatrixXcd(Eigen::VectorXcd::Constant(n, 1.0 / k).asDiagonal());
    };
    // the layered tracks at midspan and every other frequency only (the seam is the same at every x and
    // frequency; keeps the test short under the sanitizers)
    std::vector<double> f = onGroundFrequencies();
    if (!layer.empty()) {
      for (size_t i = 0; 2 * i < f.size(); ++i) f[i] = f[2 * i];
      f.resize((f.size() + 1) / 2);
    }
    for (double x : layer.empty() ? std::vector<double>{0.0, 0.36} : std::vector<double>{0.36}) {
      const double err = test::worstRelative(receptanceOnGround(rigid, x, f, ground), winkler.receptance(x, f));
      EXPECT_LT(err, 1e-9) << "x = " << x << ", layers " << layer.size();
    }
  }
}

// The CLM foundation as a ground: the masses m_f on k_f, d_f, coupled to their neighbours by k_c, d_c
// (d_c < 0), with the end layers' damping on the masses; G is the inverse of its dynamic stiffness.
// A dense, frequency-dependent, non-diagonal ground: the whole seam is exercised.
TEST(TrackOnGround, ClmGroundIsTheClmTrack) {
  const TrackParams p = test::haren();
  const TrackModel clm(withFoundation(p, FoundationModel::Clm));
  const TrackModel rigid(withFoundation(p, FoundationModel::Rigid));
  const Eigen::Index n = rigid.sleeperCount();
  const GroundCompliance ground = [&](double f) {
    const double w = 2.0 * M_PI * f;
    const Cplx kf(p.clm.stiffness_n_m, w * p.clm.damping_n_s_m);
    const Cplx kc(p.clm.coupling_stiffness_n_m, w * p.clm.coupling_damping_n_s_m);
    Eigen::MatrixXcd d = Eigen::MatrixXcd::Zero(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double eta = endDampingRate(rigid, rigid.sleeperPositions()[static_cast<size_t>(i)]);
      d(i, i) += kf - w * w * p.clm.mass_kg + Cplx(0.0, w * eta * p.clm.mass_kg);
      if (i + 1 < n) {
        d(i, i) += kc;
        d(i + 1, i + 1) += kc;
        d(i, i + 1) -= kc;
        d(i + 1, i) -= kc;
      }
    }
    return Eigen::MatrixXcd(d.inverse());
  };
  for (double x : {0.0, 0.36}) {
    const double err = test::worstRelative(receptanceOnGround(rigid, x, onGroundFrequencies(), ground),
                                           clm.receptance(x, onGroundFrequencies()));
    EXPECT_LT(err, 1e-9) << "x = " << x;
  }
}

// A ground that does not move is the rigid foundation.
TEST(TrackOnGround, RigidGroundIsTheRigidTrack) {
  const TrackModel rigid(withFoundation(test::haren(), FoundationModel::Rigid));
  const Eigen::Index n = rigid.sleeperCount();
  const GroundCompliance still = [&](double) { return Eigen::MatrixXcd(Eigen::MatrixXcd::Zero(n, n)); };
  EXPECT_LT(test::worstRelative(receptanceOnGround(rigid, 0.1, onGroundFrequencies(), still),
                                rigid.receptance(0.1, onGroundFrequencies())),
            1e-12);
}

TEST(TrackOnGround, RefusesWhatItCannotCarry) {
  const TrackParams p = test::haren();
  const TrackModel rigid(withFoundation(p, FoundationModel::Rigid));
  const Eigen::Index n = rigid.sleeperCount();
  const GroundCompliance still = [&](double) { return Eigen::MatrixXcd(Eigen::MatrixXcd::Zero(n, n)); };
  // another foundation already under the ballast, or both rails
  EXPECT_THROW(receptanceOnGround(TrackModel(withFoundation(p, FoundationModel::Clm)), 0.0, {10.0}, still),
               std::invalid_argument);
  const TrackParams full = withFoundation(
      loadTrackParams(Config::load(test::configPath("haren.yaml"), test::fixedExtent({"track.width=full"})).root()),
      FoundationModel::Rigid);
  EXPECT_THROW(receptanceOnGround(TrackModel(full), 0.0, {10.0}, still), std::invalid_argument);
  // a ground of the wrong size, or not finite
  EXPECT_THROW(
      receptanceOnGround(rigid, 0.0, {10.0}, [&](double) { return Eigen::MatrixXcd::Zero(n - 1, n - 1).eval(); }),
      std::invalid_argument);
  EXPECT_THROW(receptanceOnGround(rigid, 0.0, {10.0},
                                  [&](double) {
                                    Eigen::MatrixXcd g = Eigen::MatrixXcd::Zero(n, n);
                                    g(0, 0) = Cplx(std::nan(""), 0.0);
                                    return g;
                                  }),
               std::invalid_argument);
  EXPECT_THROW(receptanceOnGround(rigid, 0.0, {10.0}, GroundCompliance{}), std::invalid_argument);
}

}  // namespace
}  // namespace railvib::track
