// KB weighting against the DIN 45669-1 test values, DIN 4150-2 verdict,
// DIN 4150-3 guideline line, PPV and dominant frequency.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "railvib/common/constants.hpp"
#include "railvib/signal/din_check.hpp"
#include "railvib/signal/monitor.hpp"
#include "railvib/signal/vibration.hpp"

using namespace railvib::signal;
using railvib::kPi;

// DIN 45669-1 test table: continuous 1 mm/s (amplitude) sine, KB_F = steady mean, KB_Fmax = ripple maximum.
TEST(KbWeighting, Din45669TestValuesAtSeveralRates) {
  for (const double fs : {500.0, 1000.0, 2000.0, 8000.0}) {
    for (const auto& row : din45669TestTable(fs)) {
      EXPECT_NEAR(row.kb_f, row.expected_kb_f, 0.02 * row.expected_kb_f) << "f = " << row.f_hz << " fs = " << fs;
      EXPECT_NEAR(row.kb_fmax, row.expected_kb_fmax, 0.02 * row.expected_kb_fmax)
          << "f = " << row.f_hz << " fs = " << fs;
      if (fs == 1000.0) {
        std::printf("fs %.0f Hz  f %5.1f Hz  KB_F %.4f (exp %.3f)  KB_Fmax %.4f (exp %.3f)\n", fs, row.f_hz, row.kb_f,
                    row.expected_kb_f, row.kb_fmax, row.expected_kb_fmax);
      }
    }
  }
}

// The test values are the analog weighting: |H| / sqrt(2) and the ripple of an
// exponential rms; the analog formula itself reproduces them to 3 digits.
TEST(KbWeighting, AnalogFormulaReproducesTable) {
  const double f[] = {5.6, 16.0, 31.5, 80.0};
  const double kbf[] = {0.500, 0.667, 0.693, 0.594};
  const double kbfmax[] = {0.528, 0.680, 0.700, 0.597};
  for (int i = 0; i < 4; ++i) {
    const double mean = std::abs(KbWeighting::analogResponse(f[i])) / std::sqrt(2.0);
    const double x = 2.0 * 2.0 * kPi * f[i] * 0.125;
    const double mx = mean * std::sqrt(1.0 + 1.0 / std::sqrt(1.0 + x * x));
    EXPECT_NEAR(mean, kbf[i], 0.0006);
    EXPECT_NEAR(mx, kbfmax[i], 0.001);  // 5.6 Hz: 0.5274 vs the printed 0.528
  }
}

TEST(KbWeighting, DigitalResponseTracksAnalogInBuildingRange) {
  for (const double fs : {500.0, 1000.0}) {
    KbWeighting kb(fs);
    for (double f = 1.0; f <= 80.0; f *= 1.1) {
      const double d = std::abs(kb.response(f));
      const double a = std::abs(KbWeighting::analogResponse(f));
      EXPECT_NEAR(d / a, 1.0, 0.01) << "f " << f << " fs " << fs;
    }
  }
}

TEST(KbWeighting, BlockAndSampleAgree) {
  std::vector<double> v(3000);
  for (size_t i = 0; i < v.size(); ++i) v[i] = std::sin(0.05 * i) + 0.3 * std::sin(0.31 * i);
  KbWeighting a(1000.0), b(1000.0);
  std::vector<double> out(v.size());
  a.process(v.data(), v.size(), out.data());
  for (size_t i = 0; i < v.size(); ++i) EXPECT_DOUBLE_EQ(b.process(v[i]), out[i]);
  EXPECT_DOUBLE_EQ(a.kbFmax(), b.kbFmax());
}

TEST(Din4150_2, GuideValuesAndVerdict) {
  const auto day = din4150_2Residential(Din4150_2Period::Day);
  EXPECT_DOUBLE_EQ(day.a_u, 0.15);
  EXPECT_DOUBLE_EQ(day.a_o, 3.0);
  EXPECT_DOUBLE_EQ(day.a_r, 0.07);
  const auto night = din4150_2Residential(Din4150_2Period::Night);
  EXPECT_DOUBLE_EQ(night.a_u, 0.1);
  EXPECT_DOUBLE_EQ(night.a_o, 0.2);
  EXPECT_DOUBLE_EQ(night.a_r, 0.05);
  EXPECT_TRUE(din4150_2Verdict(0.1, 0.0, Din4150_2Period::Day).met);
  EXPECT_FALSE(din4150_2Verdict(3.5, 0.0, Din4150_2Period::Day).met);
  EXPECT_TRUE(din4150_2Verdict(0.5, 0.06, Din4150_2Period::Day).met);
  EXPECT_FALSE(din4150_2Verdict(0.5, 0.08, Din4150_2Period::Day).met);
  EXPECT_FALSE(din4150_2Verdict(0.25, 0.01, Din4150_2Period::Night).met);
  // KB_FTm of cycles with maxima 0.3 and 0.4: sqrt((0.09 + 0.16) / 2).
  std::vector<double> kbf(60, 0.1);
  kbf[10] = 0.3;
  kbf[40] = 0.4;
  EXPECT_NEAR(kbFTm(kbf, 1.0, 30.0), std::sqrt(0.125), 1e-12);
  EXPECT_NEAR(kbFTr(0.2, 4.0 * 3600.0, Din4150_2Period::Day), 0.1, 1e-12);
}

// DIN 4150-2 Table 1 row 3 guide values as test vectors of the procedure (section 6.5.3), with and
// without the rating KB_FTr: A_u and A_o themselves belong to the lower case ("<=").
TEST(Din4150_2, VerdictAtTheGuideValues) {
  using L = VerdictLevel;
  const auto day = Din4150_2Period::Day, night = Din4150_2Period::Night;
  struct Row {
    double kb_fmax;
    std::optional<double> kb_ftr;
    Din4150_2Period period;
    L level;
  };
  const Row rows[] = {
      {0.15, std::nullopt, day, L::Ok},
      {0.1501, std::nullopt, day, L::Warn},
      {3.0, std::nullopt, day, L::Warn},
      {3.0001, std::nullopt, day, L::Error},
      {0.1, std::nullopt, night, L::Ok},
      {0.2, std::nullopt, night, L::Warn},
      {0.2001, std::nullopt, night, L::Error},
      {0.5, 0.07, day, L::Ok},
      {0.5, 0.0701, day, L::Error},
      {0.15, 1.0, day, L::Ok},
      {0.15, 0.05, night, L::Ok},
      {0.15, 0.0501, night, L::Error},
  };
  for (const Row& r : rows) {
    const Din4150_2Verdict v = din4150_2Verdict(r.kb_fmax, r.kb_ftr, r.period);
    EXPECT_EQ(v.level, r.level) << "KB_Fmax " << r.kb_fmax << " KB_FTr " << r.kb_ftr.value_or(-1) << ": " << v.reason;
    EXPECT_EQ(v.met, r.level == L::Ok) << r.kb_fmax;
  }
}

namespace {
PpvComponent component(double ppv_mm_s, double frequency_hz) {
  PpvComponent c;
  c.ppv_mm_s = ppv_mm_s;
  c.frequency_hz = frequency_hz;
  c.limit_mm_s = din4150_3ResidentialLimitMmS(frequency_hz);
  c.ratio = ppv_mm_s / c.limit_mm_s;
  return c;
}
PpvEvaluation evaluation(const std::vector<PpvComponent>& components) {
  PpvEvaluation e;
  e.components = components;
  for (const auto& c : components) e.max_ratio = std::max(e.max_ratio, c.ratio);
  e.exceeded = e.max_ratio > 1.0;
  return e;
}
}  // namespace

// DIN 4150-3 judges each component's peak at its own frequency: 4.5 mm/s at 8 Hz (limit 5, 90 %)
// governs 12 mm/s at 50 Hz (limit 15, 80 %); the vertical governs a tie; 5.5 mm/s at 8 Hz fails.
TEST(Din4150_3, GoverningComponentIsTheClosestToItsGuideline) {
  const PpvEvaluation x_governs = evaluation({component(4.5, 8.0), component(1.0, 20.0), component(12.0, 50.0)});
  EXPECT_EQ(governingComponent(x_governs), 0u);
  const Din4150_3Verdict v = din4150_3Verdict(x_governs);
  EXPECT_TRUE(v.met);
  EXPECT_EQ(v.level, VerdictLevel::Ok);
  EXPECT_DOUBLE_EQ(v.governing.limit_mm_s, 5.0);
  EXPECT_DOUBLE_EQ(v.governing.frequency_hz, 8.0);
  // Ties: vertical first, else the first of the largest.
  EXPECT_EQ(governingComponent(evaluation({component(2.0, 8.0), component(1.0, 8.0), component(2.0, 8.0)})), 2u);
  EXPECT_EQ(governingComponent(evaluation({component(2.0, 8.0), component(2.0, 8.0), component(1.0, 8.0)})), 0u);
  EXPECT_EQ(governingComponent(evaluation({component(1.0, 8.0), component(2.0, 8.0), component(1.0, 8.0)})), 1u);
  EXPECT_EQ(governingComponent(evaluation({component(1.0, 30.0)})), 0u);
  EXPECT_EQ(governingComponent(PpvEvaluation{}), 0u);
  const Din4150_3Verdict fails = din4150_3Verdict(evaluation({component(5.5, 8.0), component(0.0, 0.0)}));
  EXPECT_FALSE(fails.met);
  EXPECT_EQ(fails.level, VerdictLevel::Error);
  EXPECT_EQ(fails.governing_component, 0u);
}

// A sensor's level: DIN 4150-2's, raised to Error by DIN 4150-3, where the standards apply (in and on
// buildings), up to the frequency the model resolves.
TEST(SensorVerdict, StandardsApplyWhereTheSensorStands) {
  const double resolved = 50.0;
  MonitorSnapshot m;
  m.kb_fmax = {0.1, 0.1, 0.5};
  m.kb_fmax_all = 0.5;  // between A_u and A_o (day): a warning without a rating
  m.ppv = evaluation({component(1.0, 20.0), component(1.0, 20.0), component(6.0, 8.0)});  // 6 > 5 mm/s at 8 Hz
  // In the free field neither standard applies: the figures stay, the verdicts say so.
  const SensorVerdict ground = sensorVerdict(m, Din4150_2Period::Day, SensorKind::FreeField, resolved);
  EXPECT_EQ(ground.level, VerdictLevel::NotApplicable) << ground.reason;
  EXPECT_EQ(ground.din4150_2.level, VerdictLevel::NotApplicable);
  EXPECT_EQ(ground.din4150_3.level, VerdictLevel::NotApplicable);
  EXPECT_EQ(ground.din4150_3.governing_component, 2u);
  EXPECT_DOUBLE_EQ(ground.din4150_3.governing.limit_mm_s, 5.0);
  // At the foundation: the curve (5 mm/s at 8 Hz) is exceeded.
  const SensorVerdict foundation = sensorVerdict(m, Din4150_2Period::Day, SensorKind::Foundation, resolved);
  EXPECT_EQ(foundation.level, VerdictLevel::Error) << foundation.reason;
  EXPECT_EQ(foundation.din4150_2.level, VerdictLevel::Warn);
  // On a floor: 20 mm/s vertical, 15 mm/s horizontal: met; DIN 4150-2 warns.
  const SensorVerdict floor = sensorVerdict(m, Din4150_2Period::Day, SensorKind::Floor, resolved);
  EXPECT_EQ(floor.level, VerdictLevel::Warn) << floor.reason;
  EXPECT_TRUE(floor.din4150_3.met);
  EXPECT_DOUBLE_EQ(floor.din4150_3.governing.limit_mm_s, kDin4150_3FloorVerticalMmS);
  EXPECT_DOUBLE_EQ(floor.din4150_3.governing.ratio, 6.0 / 20.0);
  m.ppv = evaluation({component(16.0, 20.0), component(1.0, 20.0), component(6.0, 8.0)});  // 16 > 15 horizontal
  const SensorVerdict swaying = sensorVerdict(m, Din4150_2Period::Day, SensorKind::Floor, resolved);
  EXPECT_EQ(swaying.level, VerdictLevel::Error) << swaying.reason;
  EXPECT_EQ(swaying.din4150_3.governing_component, 0u);
  // A rating decides DIN 4150-2's middle case.
  m.ppv = evaluation({component(1.0, 20.0), component(1.0, 20.0), component(1.0, 8.0)});
  EXPECT_EQ(sensorVerdict(m, Din4150_2Period::Day, SensorKind::Foundation, resolved, 0.01).level, VerdictLevel::Ok);
  m.kb_fmax_all = 0.1;
  EXPECT_EQ(sensorVerdict(m, Din4150_2Period::Day, SensorKind::Floor, resolved).level, VerdictLevel::Ok);
}

TEST(SensorVerdict, GovernedAboveTheResolvedFrequencyIsNotAssessable) {
  MonitorSnapshot m;
  m.kb_fmax = {0.05, 0.05, 0.1};
  m.kb_fmax_all = 0.1;
  // The vertical component governs both standards, its peak at 70 Hz: above a 50 Hz mesh.
  m.ppv = evaluation({component(1.0, 20.0), component(1.0, 20.0), component(16.0, 70.0)});
  const SensorVerdict v = sensorVerdict(m, Din4150_2Period::Day, SensorKind::Foundation, 50.0);
  EXPECT_EQ(v.din4150_2.level, VerdictLevel::NotAssessable);
  EXPECT_EQ(v.din4150_3.level, VerdictLevel::NotAssessable);
  EXPECT_EQ(v.level, VerdictLevel::NotAssessable) << v.reason;
  EXPECT_NE(v.reason.find("70 Hz lies above the resolved 50 Hz"), std::string::npos) << v.reason;
  // Resolved to 100 Hz, the same record is judged (16 mm/s at 70 Hz: below the curve's 17).
  EXPECT_EQ(sensorVerdict(m, Din4150_2Period::Day, SensorKind::Foundation, 100.0).level, VerdictLevel::Ok);
  // DIN 4150-2 governed by a resolved horizontal component, DIN 4150-3 by the unresolved vertical one.
  m.kb_fmax = {0.5, 0.05, 0.1};
  m.kb_fmax_all = 0.5;
  const SensorVerdict half = sensorVerdict(m, Din4150_2Period::Day, SensorKind::Foundation, 50.0);
  EXPECT_EQ(half.din4150_2.level, VerdictLevel::Warn);
  EXPECT_EQ(half.din4150_3.level, VerdictLevel::NotAssessable);
  EXPECT_EQ(half.level, VerdictLevel::Warn) << half.reason;
  EXPECT_EQ(verdictName(VerdictLevel::NotAssessable), "not assessable");
  EXPECT_EQ(sensorKindFromName(sensorKindName(SensorKind::Floor)), SensorKind::Floor);
  EXPECT_THROW(sensorKindFromName("roof"), std::invalid_argument);
}

TEST(Din4150_3, ResidentialLine) {
  EXPECT_DOUBLE_EQ(din4150_3ResidentialLimitMmS(5.0), 5.0);
  EXPECT_DOUBLE_EQ(din4150_3ResidentialLimitMmS(10.0), 5.0);
  EXPECT_DOUBLE_EQ(din4150_3ResidentialLimitMmS(30.0), 10.0);
  EXPECT_DOUBLE_EQ(din4150_3ResidentialLimitMmS(50.0), 15.0);
  EXPECT_DOUBLE_EQ(din4150_3ResidentialLimitMmS(75.0), 17.5);
  EXPECT_DOUBLE_EQ(din4150_3ResidentialLimitMmS(100.0), 20.0);
  EXPECT_DOUBLE_EQ(din4150_3ResidentialLimitMmS(250.0), 20.0);
}

TEST(Ppv, SineBurstPeakFrequencyAndVerdict) {
  // A Hann-windowed 30 Hz burst, 12 mm/s peak on z, 3 mm/s on x: z exceeds the 10 mm/s limit at 30 Hz.
  const double fs = 1000.0;
  std::vector<double> x(2000), y(2000, 0.0), z(2000);
  for (size_t i = 0; i < z.size(); ++i) {
    const double t = i / fs;
    const double env = (t > 0.5 && t < 1.5) ? 0.5 - 0.5 * std::cos(2 * kPi * (t - 0.5)) : 0.0;
    z[i] = 12.0 * env * std::sin(2 * kPi * 30.0 * t);
    x[i] = 3.0 * env * std::sin(2 * kPi * 30.0 * t + 1.0);
  }
  const auto e = evaluatePpv({x, y, z}, fs);
  ASSERT_EQ(e.components.size(), 3u);
  EXPECT_NEAR(e.components[2].ppv_mm_s, 12.0, 0.1);  // sampling of the crest at 1 kHz
  EXPECT_NEAR(e.components[2].frequency_hz, 30.0, 0.3);
  EXPECT_NEAR(e.components[2].limit_mm_s, 10.0, 0.1);
  EXPECT_NEAR(e.components[0].frequency_hz, 30.0, 0.3);
  EXPECT_NEAR(e.max_ratio, 1.2, 0.02);
  EXPECT_TRUE(e.exceeded);
  EXPECT_GE(e.vector_peak_mm_s, 12.0);
  EXPECT_LE(e.vector_peak_mm_s, std::sqrt(12.0 * 12.0 + 3.0 * 3.0));
  EXPECT_NEAR(spectralPeakFrequency(z, fs), 30.0, 0.6);
}

// The live monitor fed in arbitrary blocks gives exactly the offline record values.
TEST(VibrationMonitor, LiveEqualsOffline) {
  const double fs = 1000.0;
  const size_t n = 4000;
  std::vector<std::vector<double>> comps(3, std::vector<double>(n));
  for (size_t i = 0; i < n; ++i) {
    const double t = i / fs;
    const double env = std::exp(-std::pow((t - 2.0) / 0.3, 2));
    comps[0][i] = 1e-4 * env * std::sin(2 * kPi * 12.0 * t);
    comps[1][i] = 5e-5 * env * std::sin(2 * kPi * 40.0 * t);
    comps[2][i] = 3e-4 * env * std::sin(2 * kPi * 23.0 * t + 0.4);
  }
  MonitorSpec spec;
  spec.fs_hz = fs;
  const RecordMetrics offline = evaluateRecord(comps, spec);
  VibrationMonitor live(spec);
  std::vector<double> frames;
  size_t pos = 0, step = 1;
  while (pos < n) {
    const size_t b = std::min(n - pos, step);
    frames.clear();
    for (size_t i = pos; i < pos + b; ++i)
      for (size_t c = 0; c < 3; ++c) frames.push_back(comps[c][i]);
    live.process(frames.data(), b);
    pos += b;
    step = step * 3 % 101 + 1;
  }
  const auto s = live.snapshot();
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_DOUBLE_EQ(s.kb_fmax[c], offline.summary.kb_fmax[c]);
    EXPECT_DOUBLE_EQ(s.ppv.components[c].ppv_mm_s, offline.summary.ppv.components[c].ppv_mm_s);
    EXPECT_DOUBLE_EQ(s.third_octave_equivalent_db[c][15], offline.summary.third_octave_equivalent_db[c][15]);
  }
  EXPECT_NEAR(s.ppv.components[2].ppv_mm_s, 0.3, 0.003);
  EXPECT_NEAR(s.ppv.components[2].frequency_hz, 23.0, 0.5);
  EXPECT_NEAR(offline.spectral_peak_hz[2], 23.0, 0.5);
  EXPECT_GT(s.kb_fmax_all, 0.0);
  EXPECT_DOUBLE_EQ(s.kb_fmax_all, s.kb_fmax[2]);
}
