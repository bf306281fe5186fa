#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numeric>

#include "railvib/common/config.hpp"
#include "railvib/common/sample_stream.hpp"
#include "railvib/common/site.hpp"
#include "railvib/soil/snapshot_io.hpp"
#include "railvib/soil/soil_model.hpp"
#include "soil_test_util.hpp"
#include "test_scratch.hpp"

using namespace railvib::soil;
using railvib::Config;
using railvib::ConfigError;

using railvib::soil::testing::expectConfigError;
using railvib::soil::testing::kLoadRateHz;
using railvib::soil::testing::paramsOf;

TEST(SoilModel, BadInputIsRefusedBeforeStepping) {
  using railvib::soil::testing::smallScenario;
  expectConfigError(smallScenario("{thickness_m: 0.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, "
                                  "poisson_ratio: 0.13}"),
                    "thickness_m");
  expectConfigError(smallScenario("{thickness_m: -1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, "
                                  "poisson_ratio: 0.13}"),
                    "thickness_m");
  expectConfigError(smallScenario("{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, "
                                  "poisson_ratio: 0.5}"),
                    "poisson_ratio");
  expectConfigError(smallScenario("{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, "
                                  "poisson_ratio: 0.6}"),
                    "poisson_ratio");
  expectConfigError(smallScenario("{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, "
                                  "poisson_ratio: 0.13}",
                                  "", "[{name: far, x_m: 0.0, y_m: 8.0}]"),
                    "receiver 'far'");
  // Receiver s2 (y = 2 m) 2 m from the y_max face of the +-4 m box: inside a 3 m absorbing layer.
  std::string layered = smallScenario();
  const std::string bnd = "boundary: {method: dashpots}";
  layered.replace(layered.find(bnd), bnd.size(),
                  "boundary: {method: graded_layer, graded_layer: {thickness_m: 3.0, max_alpha_1_s: 60.0}}");
  expectConfigError(layered, "inside the 3 m absorbing zone");
  // 2 km box at 100 Hz: hundreds of GB.
  std::string big = smallScenario();
  const std::string box = "x_min_m: -4.0, x_max_m: 4.0, y_min_m: -4.0, y_max_m: 4.0, depth_m: 4.0";
  big.replace(big.find(box), box.size(),
              "x_min_m: -1000.0, x_max_m: 1000.0, y_min_m: -1000.0, y_max_m: 1000.0, depth_m: 100.0");
  big.replace(big.find("f_max_hz: 20.0"), 14, "f_max_hz: 100.0");
  expectConfigError(big, "max_memory_gb");
}

TEST(SoilModel, SleepersOutsideTheBoxAreDropped) {
  const SoilParams p = paramsOf(railvib::soil::testing::smallScenario());
  SoilModel model(p, {0.0, 0.72}, kLoadRateHz);
  ASSERT_EQ(model.sleeperCount(), 2u);
  EXPECT_TRUE(model.droppedSleepers().empty());
  // Dropped: a sleeper outside the box.
  SoilModel model2(p, {0.0, 10.0}, kLoadRateHz);
  EXPECT_EQ(model2.droppedSleepers().size(), 1u);
}

TEST(SoilModel, StreamingInBlocksEqualsOneBlockAndChecksContinuity) {
  const SoilParams p = paramsOf(railvib::soil::testing::smallScenario());
  const std::vector<double> xs = {-0.72, 0.0, 0.72};
  const size_t frames = 201;  // 0.1 s at 2 kHz
  std::vector<double> loads(frames * xs.size());
  for (size_t f = 0; f < frames; ++f) {
    for (size_t s = 0; s < xs.size(); ++s) {
      const double t = f / 2000.0;
      loads[f * xs.size() + s] = 1e4 * std::exp(-std::pow((t - 0.02 - 0.005 * s) / 0.004, 2));
    }
  }
  auto runModel = [&](size_t block) {
    SoilModel m(p, xs, kLoadRateHz);
    ReceiverBlock rb;
    std::vector<double> all;
    std::vector<SurfaceSnapshot> snaps;
    for (size_t f0 = 0; f0 < frames; f0 += block) {
      const size_t nf = std::min(block, frames - f0);
      m.pushLoads(f0, &loads[f0 * xs.size()], nf);
      m.advance(1e9);
      m.takeReceiverSamples(rb);
      all.insert(all.end(), rb.velocity_m_s.begin(), rb.velocity_m_s.end());
    }
    m.finishLoads();
    m.advance(0.1);
    m.finishOutputs();
    m.takeReceiverSamples(rb);
    all.insert(all.end(), rb.velocity_m_s.begin(), rb.velocity_m_s.end());
    m.takeSnapshots(snaps);
    EXPECT_THROW(m.pushLoads(5, &loads[0], 1), railvib::StreamGapError);
    return std::make_pair(all, snaps);
  };
  const auto a = runModel(frames);
  const auto b = runModel(17);
  ASSERT_EQ(a.first.size(), b.first.size());
  ASSERT_GT(a.first.size(), 3u * 90);
  double peak = 0.0;
  for (size_t i = 0; i < a.first.size(); ++i) {
    EXPECT_DOUBLE_EQ(a.first[i], b.first[i]);
    peak = std::max(peak, std::abs(a.first[i]));
  }
  EXPECT_GT(peak, 0.0);
  // About 10 snapshots for 0.1 s at 100 Hz, on the surface grid; roundtrip through the binary file.
  ASSERT_GE(a.second.size(), 9u);
  const railvib::test::ScratchDir scratch("soil_snapshots");
  const std::string path = scratch.file("surface.snap").string();
  writeSnapshots(path, a.second);
  const auto back = readSnapshots(path);
  ASSERT_EQ(back.size(), a.second.size());
  EXPECT_EQ(back[3].vz_up_m_s, a.second[3].vz_up_m_s);
  EXPECT_DOUBLE_EQ(back[3].time_s, 0.03);
}

TEST(SoilModel, DownwardLoadMovesTheSurfaceDown) {
  // A slowly applied downward load under the receiver: vertical (up) velocity is negative first.
  SoilParams p = paramsOf(railvib::soil::testing::smallScenario(
      "{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, poisson_ratio: 0.13}", "",
      "[{name: s0, x_m: 0.0, y_m: 0.0}]"));
  p.receivers.resize(1);
  SoilModel m(p, {0.0}, kLoadRateHz);
  std::vector<double> loads(101);
  for (size_t f = 0; f < loads.size(); ++f) loads[f] = 1e4 * std::min(1.0, f / 40.0);
  m.pushLoads(0, loads);
  m.finishLoads();
  m.advance(0.02);
  m.finishOutputs();
  ReceiverBlock rb;
  m.takeReceiverSamples(rb);
  double vmin = 0.0;
  for (size_t f = 0; f < rb.frames(); ++f) vmin = std::min(vmin, rb.velocity_m_s[3 * f + 2]);
  EXPECT_LT(vmin, 0.0);
}

TEST(SoilModel, FinishRunEndsOneStepPastTheLastLoadWhateverTheRounding) {
  // The accumulated step time can land a hair below t_end (within advance()'s 1e-9 dt tolerance):
  // the end of a run must still terminate, hold the last load and emit the receiver frame at t_end.
  SoilParams p = paramsOf(railvib::soil::testing::smallScenario(
      "{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, poisson_ratio: 0.13}", "",
      "[{name: s0, x_m: 0.0, y_m: 0.0}]"));
  p.receivers.resize(1);
  const double load_rate_hz = kLoadRateHz;
  for (const double t_end : {0.0137, 0.0180, 0.0235, 0.0301}) {
    SoilModel m(p, {0.0}, kLoadRateHz);
    const size_t frames = static_cast<size_t>(std::llround(t_end * load_rate_hz)) + 1;
    std::vector<double> loads(frames);
    for (size_t f = 0; f < frames; ++f) loads[f] = 1e4 * std::sin(200.0 * f / load_rate_hz);
    m.pushLoads(0, loads);
    m.finishLoads();
    int slices = 0;
    const uint64_t steps = m.finishRun(t_end, 0.004, [&] { return ++slices < 1000; });
    EXPECT_LT(slices, 1000) << "t_end " << t_end;
    EXPECT_GE(m.time(), t_end - 1e-9 * m.dt()) << "t_end " << t_end;
    EXPECT_LE(m.time(), t_end + 2.0 * m.dt()) << "t_end " << t_end;
    EXPECT_EQ(steps, m.solver().stepCount());
    ReceiverBlock rb;
    m.takeReceiverSamples(rb);
    // Every receiver frame up to t_end exists, none beyond the last step.
    EXPECT_GE(rb.frames(), static_cast<size_t>(std::floor(t_end * p.receiver_rate_hz + 1e-9)) + 1) << t_end;
    EXPECT_LE(rb.frames(), static_cast<size_t>(std::floor(m.time() * p.receiver_rate_hz + 1e-9)) + 1) << t_end;
  }
}

// The vertical section (paper, Fig. 16) and the surface snapshots are two views of one field: the
// section's surface row equals the surface snapshot's column at the section's x, component by
// component, and a load on the track axis of a box symmetric in x and y gives mirror symmetry:
// vz and vx even in y, vy odd in y (the horizontal motion points away from the load on both sides);
// on the surface vx is odd in x about the load, vy and vz even.
TEST(SoilModel, SnapshotsAreOneThreeComponentFieldWithTheLoadsMirrorSymmetry) {
  SoilParams p = paramsOf(railvib::soil::testing::smallScenario());
  p.section_enabled = true;
  p.section_x_m = 0.0;
  p.receivers.clear();
  ASSERT_TRUE(p.snapshot_horizontal);  // the default: all three components
  // A Gaussian pulse on the track axis at x = 0; the snapshots of the run and its mesh.
  std::vector<SurfaceSnapshot> surf;
  std::vector<SectionSnapshot> sect;
  const auto run = [](const SoilParams& params, std::vector<SurfaceSnapshot>& surface,
                      std::vector<SectionSnapshot>& section) {
    SoilModel m(params, {0.0}, 2000.0);
    std::vector<double> loads(201);
    for (size_t f = 0; f < loads.size(); ++f) loads[f] = 1e4 * std::exp(-std::pow((f / 2000.0 - 0.02) / 0.004, 2));
    m.pushLoads(0, loads.data(), loads.size());
    m.finishLoads();
    m.finishRun(0.1, 0.05);
    m.takeSnapshots(surface);
    m.takeSectionSnapshots(section);
    return m.solver().mesh();
  };
  const StructuredMesh mesh = run(p, surf, sect);
  ASSERT_EQ(surf.size(), sect.size());
  ASSERT_GT(sect.size(), 5u);
  ASSERT_NEAR(mesh.x0, -mesh.xMax(), 1e-12);  // the mirror in x below needs a box symmetric about the load
  ASSERT_NEAR(mesh.y0, -mesh.yMax(), 1e-12);
  const size_t i = static_cast<size_t>(std::lround((0.0 - mesh.x0) / mesh.hx));
  const size_t nsx = mesh.nx + 1, nsy = mesh.ny + 1;
  struct Component {
    const char* name;
    std::vector<float> SurfaceSnapshot::*surface;
    std::vector<float> SectionSnapshot::*section;
    double parity_y, parity_x;  // +1 even, -1 odd
  };
  const Component components[] = {{"vx", &SurfaceSnapshot::vx_m_s, &SectionSnapshot::vx_m_s, 1.0, -1.0},
                                  {"vy", &SurfaceSnapshot::vy_m_s, &SectionSnapshot::vy_m_s, -1.0, 1.0},
                                  {"vz", &SurfaceSnapshot::vz_up_m_s, &SectionSnapshot::vz_up_m_s, 1.0, 1.0}};
  double peak_vz = 0.0;
  for (const Component& c : components) {
    double peak = 0.0, asym = 0.0;
    for (size_t s = 0; s < sect.size(); ++s) {
      ASSERT_EQ(sect[s].index, surf[s].index);
      const std::vector<float>& plane = sect[s].*c.section;
      const std::vector<float>& top = surf[s].*c.surface;
      ASSERT_EQ(plane.size(), nsy * (mesh.nz + 1)) << c.name;
      ASSERT_EQ(top.size(), nsx * nsy) << c.name;
      for (size_t j = 0; j < nsy; ++j) {
        EXPECT_EQ(plane[j], top[j * nsx + i]) << c.name;
        for (size_t k = 0; k <= mesh.nz; ++k) {
          const double v = plane[k * nsy + j], mirror = plane[k * nsy + (nsy - 1 - j)];
          peak = std::max(peak, std::abs(v));
          asym = std::max(asym, std::abs(v - c.parity_y * mirror));
        }
        for (size_t ix = 0; ix < nsx; ++ix) {
          const double v = top[j * nsx + ix], mirror = top[j * nsx + (nsx - 1 - ix)];
          peak = std::max(peak, std::abs(v));
          asym = std::max(asym, std::abs(v - c.parity_x * mirror));
        }
      }
    }
    if (c.parity_y > 0.0 && c.parity_x > 0.0) peak_vz = peak;
    EXPECT_GT(peak, 1e-6) << c.name;
    EXPECT_LT(asym, 1e-4 * std::max(peak, peak_vz)) << c.name;
  }

  // Vertical only: the same vertical field, no horizontal ones.
  p.snapshot_horizontal = false;
  std::vector<SurfaceSnapshot> surf_v;
  std::vector<SectionSnapshot> sect_v;
  run(p, surf_v, sect_v);
  ASSERT_EQ(surf_v.size(), surf.size());
  for (size_t s = 0; s < surf.size(); ++s) {
    EXPECT_EQ(surf_v[s].vz_up_m_s, surf[s].vz_up_m_s);
    EXPECT_EQ(sect_v[s].vz_up_m_s, sect[s].vz_up_m_s);
    EXPECT_TRUE(surf_v[s].vx_m_s.empty() && surf_v[s].vy_m_s.empty());
    EXPECT_TRUE(sect_v[s].vx_m_s.empty() && sect_v[s].vy_m_s.empty());
  }
}

// A value shared with other domains is read by its own loader only: a bad one is refused by the soil
// with exactly the message (key, value, the one range, file) of that loader.
TEST(SoilParams, SharedValuesAreRefusedByTheirOneLoader) {
  const std::string haren = std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml";
  auto message = [&](const std::string& override_value, const std::function<void(const railvib::ConfigNode&)>& load) {
    try {
      load(Config::load(haren, {override_value}).root());
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const auto soil = [](const railvib::ConfigNode& root) { loadSoilParams(root); };
  const auto site = [](const railvib::ConfigNode& root) { railvib::loadSiteLayout(root); };
  const auto track = [](const railvib::ConfigNode& root) { railvib::loadTrackLayout(root); };
  const std::string gauge = message("site.rail_gauge_m=5.0", site);
  EXPECT_NE(gauge.find("site.rail_gauge_m = 5"), std::string::npos) << gauge;
  EXPECT_NE(gauge.find("(0.5, 2)"), std::string::npos) << gauge;
  EXPECT_EQ(message("site.rail_gauge_m=5.0", soil), gauge);
  const std::string spacing = message("track.sleeper.spacing_m=6.0", track);
  EXPECT_NE(spacing.find("[0.05, 5]"), std::string::npos) << spacing;
  EXPECT_EQ(message("track.sleeper.spacing_m=6.0", soil), spacing);
  // (an automatic extent: a run the soil and the track read alike)
  const std::string extent = message("simulation.duration_s=-1", track);
  EXPECT_NE(extent.find("simulation.duration_s = -1"), std::string::npos) << extent;
  EXPECT_EQ(message("simulation.duration_s=-1", soil), extent);
  const std::string margin = message("track.extent.margin_m=-1", track);
  EXPECT_NE(margin.find("track.extent.margin_m = -1"), std::string::npos) << margin;
  EXPECT_EQ(message("track.extent.margin_m=-1", soil), margin);
}

namespace {
// The small scenario in double precision with receivers mirrored about the track axis.
SoilParams seatParams() {
  return paramsOf(railvib::soil::testing::smallScenario(
      "{thickness_m: 1.0, young_modulus_pa: 61.0e6, density_kg_m3: 1876.0, poisson_ratio: 0.13}", ", precision: double",
      "[{name: a, x_m: 0.3, y_m: 2.0}, {name: b, x_m: 0.3, y_m: -2.0}]"));
}

// 0.1 s of receiver velocities under per-frame loads built by `load(frame, sleeper, seat)`.
std::vector<double> seatRun(const SoilParams& p, const std::vector<double>& seats,
                            const std::function<double(size_t, size_t, size_t)>& load) {
  const std::vector<double> xs = {-0.72, 0.0, 0.72};
  SoilModel m(p, xs, seats, kLoadRateHz);
  const size_t per = m.loadsPerSleeper(), frames = 201;
  std::vector<double> loads(frames * xs.size() * per);
  for (size_t f = 0; f < frames; ++f) {
    for (size_t s = 0; s < xs.size(); ++s) {
      for (size_t k = 0; k < per; ++k) loads[(f * xs.size() + s) * per + k] = load(f, s, k);
    }
  }
  m.pushLoads(0, loads);
  m.finishLoads();
  m.advance(0.1);
  m.finishOutputs();
  ReceiverBlock rb;
  m.takeReceiverSamples(rb);
  return rb.velocity_m_s;
}

double pulse(size_t frame, size_t sleeper) {
  const double t = frame / kLoadRateHz;
  return 1e4 * std::exp(-std::pow((t - 0.02 - 0.005 * sleeper) / 0.004, 2));
}
}  // namespace

// A full-width track's soil loads per rail seat (issue 17): both seats loaded alike are the half track's
// both-rails load on the footprint, to round-off; in anti-phase the field is mirror-antisymmetric about
// the track axis (v_z and v_x odd in y, v_y even), a pure roll moment.
TEST(SoilModel, RailSeatLoadsAreTheFootprintInPhaseAndARollMomentInAntiPhase) {
  const SoilParams p = seatParams();
  const std::vector<double> seats = {0.7175, -0.7175};
  const auto whole = seatRun(p, {}, [](size_t f, size_t s, size_t) { return 2.0 * pulse(f, s); });
  const auto alike = seatRun(p, seats, [](size_t f, size_t s, size_t) { return pulse(f, s); });
  ASSERT_EQ(whole.size(), alike.size());
  ASSERT_GT(whole.size(), 6u * 90);
  double peak = 0.0, diff = 0.0;
  for (size_t i = 0; i < whole.size(); ++i) {
    peak = std::max(peak, std::abs(whole[i]));
    diff = std::max(diff, std::abs(whole[i] - alike[i]));
  }
  EXPECT_GT(peak, 0.0);
  EXPECT_LT(diff, 1e-12 * peak);

  const auto anti = seatRun(p, seats, [](size_t f, size_t s, size_t k) { return (k == 0 ? 1.0 : -1.0) * pulse(f, s); });
  double anti_peak = 0.0, asym = 0.0;
  for (size_t f = 0; f < anti.size() / 6; ++f) {
    const double* a = &anti[6 * f];
    const double* b = a + 3;
    asym = std::max({asym, std::abs(a[0] + b[0]), std::abs(a[1] - b[1]), std::abs(a[2] + b[2])});
    anti_peak = std::max({anti_peak, std::abs(a[0]), std::abs(a[1]), std::abs(a[2])});
  }
  EXPECT_GT(anti_peak, 0.05 * peak);  // a roll moment of 1.4 m x the load moves the ground
  EXPECT_LT(asym, 1e-12 * anti_peak);
  std::printf("rail seats: in phase - footprint %.1e of the peak; anti-phase peak %.2f of it, mirror error %.1e\n",
              diff / peak, anti_peak / peak, asym / anti_peak);
  // A seat off the footprint is refused.
  EXPECT_THROW(SoilModel(p, {0.0}, {1.4}, kLoadRateHz), std::invalid_argument);
  EXPECT_THROW(SoilModel(p, {0.0}, {std::nan("")}, kLoadRateHz), std::invalid_argument);
}
