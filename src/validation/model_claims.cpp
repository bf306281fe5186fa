// The claims the models check without a soil run: track receptance (paper section 2.2, Fig. 4),
// vehicle modes (section 3.2, Fig. 9, Table 1), wheel impedances (Fig. 10), the defect (Fig. 7),
// the impact times (section 3.5) and the building (section 3.4, Figs. 13-14).
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <utility>

#include "railvib/building/modal.hpp"
#include "railvib/building/model.hpp"
#include "railvib/building/params.hpp"
#include "railvib/building/response.hpp"
#include "railvib/coupling/track_on_soil.hpp"
#include "railvib/soil/footprint_compliance.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/track/track_analysis.hpp"
#include "railvib/track/track_model.hpp"
#include "railvib/validation/validation.hpp"
#include "railvib/vehicle/modal.hpp"
#include "railvib/vehicle/passage.hpp"
#include "railvib/vehicle/unevenness.hpp"
#include "vehicle_summary.hpp"

namespace railvib::validation {

std::string verdictName(Verdict v) {
  switch (v) {
    case Verdict::Agrees:
      return "agrees";
    case Verdict::Differs:
      return "differs";
    case Verdict::Pending:
      break;
  }
  return "pending";
}

Claim claim(std::string id, std::string topic, std::string paper, std::string criterion) {
  Claim c;
  c.id = std::move(id);
  c.topic = std::move(topic);
  c.paper = std::move(paper);
  c.criterion = std::move(criterion);
  return c;
}

nlohmann::json toJson(const Claim& c) {
  return {{"id", c.id},
          {"topic", c.topic},
          {"paper", c.paper},
          {"criterion", c.criterion},
          {"ours", c.ours},
          {"verdict", verdictName(c.verdict)},
          {"expected", verdictName(c.expected)},
          {"regressed", c.regressed()},
          {"command", c.command},
          {"cause", c.cause}};
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

namespace {

const char* kConfig = "--config config/haren.yaml";

// ------------------------------------------------------------------ track
/// Resonance peaks of the rail receptance at the sleeper nearest x = 0, below 0.8 f_pp.
std::vector<double> trackPeaks(const track::TrackParams& p) {
  const track::TrackModel model(p);
  const double x0 = model.sleeperPositions()[static_cast<size_t>(model.nearestSleeper(0.0))];
  std::vector<double> f;
  for (double v = 1.0; v <= 200.0 + 1e-9; v += 0.25) f.push_back(v);
  const double fpp = track::pinnedPinnedFrequency(p);
  std::vector<double> out;
  for (const auto& pk : track::findPeaks(f, model.receptance(x0, f))) {
    if (pk.frequency_hz < 0.8 * fpp) out.push_back(pk.frequency_hz);
  }
  return out;
}

track::TrackParams withFoundation(track::TrackParams p, track::FoundationModel m) {
  p.foundation = m;
  return p;
}

track::TrackParams scaled(track::TrackParams p, double kb, double kf) {
  p.ballast_stiffness_n_m *= kb;
  p.clm.stiffness_n_m *= kf;
  p.winkler.stiffness_n_m *= kf;
  return p;
}

double peakOr(const std::vector<double>& peaks, size_t i) {
  return i < peaks.size() ? peaks[i] : std::numeric_limits<double>::quiet_NaN();
}

void trackClaims(const Config& cfg, std::vector<Claim>& out) {
  const track::TrackParams base = track::loadTrackParams(cfg.root());
  const track::TrackParams clm = withFoundation(base, track::FoundationModel::Clm);
  const track::TrackParams wink = withFoundation(base, track::FoundationModel::Winkler);
  const std::vector<double> pc = trackPeaks(clm), pw = trackPeaks(wink);
  const double f_clm = peakOr(pc, 1), f_wink = peakOr(pw, 0);
  {
    Claim c =
        claim("track.first_resonance.winkler", "track",
              "the first resonance frequency of the track is ~70 Hz (section 3.2, from the Winkler-track study of "
              "ref. 17)",
              "Winkler track resonance at a sleeper within 10 % of 70 Hz");
    c.ours = fixed(f_wink, 1) + " Hz";
    c.verdict = verdictOf(std::abs(f_wink / 70.0 - 1.0) <= 0.10);
    c.expected = Verdict::Agrees;
    c.command = std::string("railvib_tool receptance ") + kConfig + " --foundation winkler --csv r.csv";
    out.push_back(c);
  }
  {
    Claim c =
        claim("track.first_resonance.clm", "track", "the same ~70 Hz for the CLM track of this paper (section 3.2)",
              "CLM out-of-phase (rail/sleeper on ballast) resonance at a sleeper within 10 % of 70 Hz");
    c.ours = fixed(f_clm, 1) + " Hz (in-phase foundation bounce " + fixed(peakOr(pc, 0), 1) + " Hz)";
    c.verdict = verdictOf(std::abs(f_clm / 70.0 - 1.0) <= 0.10);
    c.expected = Verdict::Differs;
    c.command = std::string("railvib_tool receptance ") + kConfig + " --foundation clm --csv r.csv";
    c.cause =
        "the CLM holds the soil up to 50 Hz (T6), not above: at 78 Hz its 2502 kg foundation mass hardly moves, so "
        "the rail and sleeper bounce on k_b alone. The same track on the FE soil (receptance --foundation fe_soil on "
        "a 100 Hz mesh, docs/validation.md 'The track on the FE soil') resonates at 70.9 Hz, the paper's ~70 Hz, and "
        "ref. 17's Winkler track (71.6 Hz) follows it within 0.6 dB over 50-100 Hz. Not the sleeper mass (45 kg per "
        "rail seat [assumed]): 90 kg gives CLM 67.3 Hz but Winkler 61.0 Hz";
    out.push_back(c);
  }
  // k_b and k_f dependence (Fig. 4): factor 2 on each
  const std::vector<double> pc_kb = trackPeaks(scaled(clm, 2.0, 1.0)), pw_kb = trackPeaks(scaled(wink, 2.0, 1.0));
  const std::vector<double> pc_kf = trackPeaks(scaled(clm, 1.0, 2.0)), pw_kf = trackPeaks(scaled(wink, 1.0, 2.0));
  const double r_clm_kb = peakOr(pc_kb, 1) / f_clm, r_wink_kb = peakOr(pw_kb, 0) / f_wink;
  const double r_clm_kf = peakOr(pc_kf, 1) / f_clm, r_wink_kf = peakOr(pw_kf, 0) / f_wink;
  const double r_clm_first_kb = peakOr(pc_kb, 0) / peakOr(pc, 0);
  {
    Claim c =
        claim("track.kb_dependence", "track",
              "the frequencies of the modes (in-phase and out-of-phase motions of rail and ballast) depend on k_b "
              "(section 2.2, Fig. 4)",
              "doubling k_b raises the rail/ballast resonance by > 20 % (CLM and Winkler)");
    c.ours = "x2 k_b: CLM out-of-phase x" + fixed(r_clm_kb, 2) + ", Winkler x" + fixed(r_wink_kb, 2);
    c.verdict = verdictOf(r_clm_kb > 1.2 && r_wink_kb > 1.2);
    c.expected = Verdict::Agrees;
    c.command = std::string("railvib_tool receptance ") + kConfig + " --vary kb --csv r.csv";
    out.push_back(c);
  }
  {
    Claim c = claim("track.kb_dependence.first_mode", "track",
                    "the first mode (in-phase) depends on k_b too (section 2.2, Fig. 4)",
                    "doubling k_b moves the CLM's lowest peak by > 5 %");
    c.ours = "x2 k_b: CLM lowest peak x" + fixed(r_clm_first_kb, 3) + " (" + fixed(peakOr(pc, 0), 1) + " Hz)";
    c.verdict = verdictOf(std::abs(r_clm_first_kb - 1.0) > 0.05);
    c.expected = Verdict::Differs;
    c.command = std::string("railvib_tool receptance ") + kConfig + " --vary kb --csv r.csv";
    c.cause =
        "with the paper's CLM values the lowest peak is the bounce of the 2502 kg foundation masses on k_f and "
        "k_c (sqrt(k_f / m_f) / 2 pi = 17 Hz); the light rail and sleeper ride on it, k_b hardly deforms: it moves "
        "with k_f (x2 k_f: 14.8 -> 22.2 Hz), the paper's 'to a lesser degree on k_f (for soft soil)'";
    out.push_back(c);
  }
  {
    Claim c = claim("track.kf_dependence", "track", "... and to a lesser degree on k_f (section 2.2, Fig. 4)",
                    "doubling k_f moves the rail/ballast resonance less than doubling k_b does");
    c.ours = "x2 k_f: CLM out-of-phase x" + fixed(r_clm_kf, 3) + ", Winkler x" + fixed(r_wink_kf, 3);
    c.verdict = verdictOf(std::abs(r_clm_kf - 1.0) < std::abs(r_clm_kb - 1.0) &&
                          std::abs(r_wink_kf - 1.0) < std::abs(r_wink_kb - 1.0));
    c.expected = Verdict::Agrees;
    c.command = std::string("railvib_tool receptance ") + kConfig + " --vary kf --csv r.csv";
    out.push_back(c);
  }
}

/// 20 log10 |a / b| (dB) at each frequency of two curves on one grid.
std::vector<double> levelDifferenceDb(const std::vector<std::complex<double>>& a,
                                      const std::vector<std::complex<double>>& b) {
  std::vector<double> out;
  for (size_t i = 0; i < a.size(); ++i) out.push_back(20.0 * std::log10(std::abs(a[i]) / std::abs(b[i])));
  return out;
}
double maxAbs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}
double rmsOf(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

// The CLM against the track on the FE soil (section 2.2, Fig. 4): one soil impulse run of the scenario's
// soil, the same rail, pads, sleepers and ballast on it, at the sleeper nearest x = 0, 1-50 Hz.
void rigorousTrackClaims(const Config& cfg, const ValidationOptions& opt, std::vector<Claim>& out) {
  const std::string command =
      std::string("railvib_tool receptance ") + kConfig + " --foundation fe_soil|clm|winkler --fmax 50 --csv r.csv";
  Claim follows = claim("track.clm_vs_rigorous_fem", "track",
                        "the CLM receptance follows the rigorous FE track-soil model up to 50 Hz, also on soft soil "
                        "(section 2.2, Fig. 4)",
                        "the CLM's in-phase resonance within 5 % of the FE track-soil model's (the scenario's soil, "
                        "the chain's step 2), and |CLM| / |FE| within +-3 dB over 1-50 Hz");
  follows.expected = Verdict::Agrees;
  follows.command = command;
  Claim better = claim("track.clm_better_than_winkler", "track",
                       "the CLM extends the Winkler model and better represents the track-soil coupling (sections 2, "
                       "3.2: ref. 17's Winkler track 'is now improved by the CLM model, which can more accurately "
                       "represent a rigorous model')",
                       "rms of the level difference to the FE track-soil receptance over 1-50 Hz smaller for the CLM "
                       "than for the Winkler track (k_b / k_f = 0.26)");
  better.expected = Verdict::Agrees;
  better.command = command;
  if (opt.quick) {
    for (Claim* c : {&follows, &better}) {
      c->ours = "not computed with --quick (one soil impulse run, minutes)";
      out.push_back(*c);
    }
    return;
  }
  const track::TrackParams base = track::loadTrackParams(cfg.root());
  const soil::FootprintCompliance soil =
      soil::FootprintCompliance(soil::loadSoilParams(cfg.root()), soil::FootprintComplianceSpec{});
  const track::TrackModel probe(base);
  const double x0 = probe.sleeperPositions()[static_cast<size_t>(probe.nearestSleeper(0.0))];
  std::vector<double> f;
  for (double v = 1.0; v <= std::min(50.0, soil.maxFrequencyHz()) + 1e-9; v += 0.25) f.push_back(v);
  const auto fe = coupling::feSoilReceptance(base, soil, x0, f);
  const auto fe_half_reach = coupling::feSoilReceptance(base, soil, x0, f, (soil.distanceCount() - 1) / 2);
  const auto clm = track::TrackModel(withFoundation(base, track::FoundationModel::Clm)).receptance(x0, f);
  const auto wink = track::TrackModel(withFoundation(base, track::FoundationModel::Winkler)).receptance(x0, f);
  const std::vector<double> d_clm = levelDifferenceDb(clm, fe), d_wink = levelDifferenceDb(wink, fe);
  const double reach_effect = maxAbs(levelDifferenceDb(fe_half_reach, fe));
  const auto pf = track::findPeaks(f, fe), pcl = track::findPeaks(f, clm);
  const double f_fe = pf.empty() ? std::nan("") : pf.front().frequency_hz;
  const double f_clm = pcl.empty() ? std::nan("") : pcl.front().frequency_hz;
  size_t worst = 0;
  for (size_t i = 0; i < d_clm.size(); ++i) {
    if (std::abs(d_clm[i]) > std::abs(d_clm[worst])) worst = i;
  }
  follows.ours = "in-phase resonance CLM " + fixed(f_clm, 1) + " Hz, FE " + fixed(f_fe, 1) + " Hz; |CLM| / |FE| " +
                 fixed(d_clm[worst], 1) + " dB at worst (" + fixed(f[worst], 1) + " Hz), rms " +
                 fixed(rmsOf(d_clm), 1) + " dB (FE soil reach " +
                 fixed(soil.spacingM() * static_cast<double>(soil.distanceCount() - 1), 1) +
                 " m: half of it moves the FE curve by " + fixed(reach_effect, 2) + " dB)";
  follows.verdict = verdictOf(std::abs(f_clm / f_fe - 1.0) <= 0.05 && maxAbs(d_clm) <= 3.0);
  out.push_back(follows);
  better.ours = "rms level difference to FE over 1-50 Hz: CLM " + fixed(rmsOf(d_clm), 2) + " dB, Winkler " +
                fixed(rmsOf(d_wink), 2) + " dB";
  better.verdict = verdictOf(rmsOf(d_clm) < rmsOf(d_wink));
  out.push_back(better);
}

// ------------------------------------------------------------------ vehicle
void vehicleClaims(const Config& cfg, std::vector<Claim>& out) {
  const vehicle::VehicleModel model(vehicle::loadVehicleParams(cfg.root(), "t2000"));
  const track::TrackParams base = track::loadTrackParams(cfg.root());
  const VehicleModeSummary rigid = summarise(model, vehicle::vehicleModesRigid(model));
  const VehicleModeSummary clm =
      summarise(model, vehicle::vehicleModesFlexible(model, withFoundation(base, track::FoundationModel::Clm)));
  const VehicleModeSummary wink =
      summarise(model, vehicle::vehicleModesFlexible(model, withFoundation(base, track::FoundationModel::Winkler)));
  const std::string modes_cmd = std::string("railvib_tool vehicle-modes ") + kConfig + " --track rigid|flexible";
  {
    Claim c = claim("vehicle.carbody_bounce", "vehicle", "car-body-on-suspension bounce between 2 and 3 Hz (Fig. 9)",
                    "lowest car-body bounce (rigid track) in [2, 3] Hz");
    c.ours = fixed(rigid.carbody_bounce_hz, 2) + " Hz";
    c.verdict = verdictOf(rigid.carbody_bounce_hz >= 2.0 && rigid.carbody_bounce_hz <= 3.0);
    c.expected = Verdict::Agrees;
    c.command = modes_cmd;
    out.push_back(c);
  }
  {
    Claim c = claim("vehicle.bogie_bounce", "vehicle", "bogie bounce mode at around 20 Hz (Fig. 9)",
                    "lowest leading-bogie mode within 15 % of 20 Hz, rigid and Winkler track");
    c.ours = fixed(rigid.bogie_first_hz, 1) + " Hz rigid (turns " + fixed(-rigid.bogie_first_pivot_m, 2) +
             " m ahead of the bogie centre), " + fixed(wink.bogie_first_hz, 1) + " Hz Winkler, " +
             fixed(clm.bogie_first_hz, 1) + " Hz CLM";
    c.verdict = verdictOf(std::abs(rigid.bogie_first_hz / 20.0 - 1.0) <= 0.15 &&
                          std::abs(wink.bogie_first_hz / 20.0 - 1.0) <= 0.15);
    c.expected = Verdict::Agrees;
    c.command = modes_cmd;
    out.push_back(c);
  }
  {
    Claim c =
        claim("vehicle.bogie_pitch_about_motor_axle", "vehicle",
              "bogie pitch modes at 22-24 Hz dominate the ground response (sections 3.3, 3.5)",
              "a leading-bogie mode in [21, 25] Hz in which the bogie turns about a point within 0.5 m of an axle "
              "(rigid or CLM)");
    c.ours = fixed(rigid.bogie_first_hz, 1) + " Hz rigid, pivot " + fixed(rigid.bogie_first_pivot_to_axle_m, 2) +
             " m from the motor axle; CLM " + fixed(clm.bogie_first_hz, 1) + " Hz";
    const bool rigid_ok =
        rigid.bogie_first_hz >= 21.0 && rigid.bogie_first_hz <= 25.0 && rigid.bogie_first_pivot_to_axle_m <= 0.5;
    c.verdict = verdictOf(rigid_ok || (clm.bogie_first_hz >= 21.0 && clm.bogie_first_hz <= 25.0));
    c.expected = Verdict::Agrees;
    c.command = modes_cmd;
    c.cause =
        "interpretation: the (A1) bogie swinging about its heavy hub-motor wheel is our candidate for the paper's "
        "22-24 Hz bogie pitch (our kinematic naming calls it a bounce: the pivot lies just outside the wheelbase)";
    out.push_back(c);
  }
  {
    Claim c =
        claim("vehicle.bogie_pure_pitch", "vehicle", "a bogie pitch (about the bogie centre) at 22-24 Hz (section 3.5)",
              "leading-bogie mode turning within half the half-wheelbase of its centre, in [21, 25] Hz");
    c.ours = fixed(rigid.bogie_pitch_hz, 1) + " Hz rigid, " + fixed(clm.bogie_pitch_hz, 1) + " Hz CLM";
    c.verdict = verdictOf(rigid.bogie_pitch_hz >= 21.0 && rigid.bogie_pitch_hz <= 25.0);
    c.expected = Verdict::Differs;
    c.command = modes_cmd;
    c.cause =
        "with k_m = 44 MN/m and k_d = 5.88 MN/m at +-0.83 m and I_b = 300 kg m^2 the pure pitch cannot be near "
        "22 Hz in any reading of the appendix (45-101 Hz, docs/validation.md 'Readings'); it would need a ~10x "
        "pitch inertia or ~10x softer primary";
    out.push_back(c);
  }
  // Table 1: 5-20 % decrease of f0 of the first three modes with the flexible track
  struct Drop {
    const char* id;
    const char* what;
    double rigid_hz, clm_hz, wink_hz;
    Verdict expected;
    const char* cause;
  } drops[] = {
      {"vehicle.flexible_drop.carbody_bounce", "car-body bounce", rigid.carbody_bounce_hz, clm.carbody_bounce_hz,
       wink.carbody_bounce_hz, Verdict::Differs,
       "the secondary k_2 = 0.96 MN/m is ~40x softer than the primary + track below it (static track stiffness "
       "~39 MN/m per wheel, railvib_tool receptance): the series combination moves the bounce by < 1 %; a 5 % drop "
       "needs ~9 MN/m under each bogie side, no reading of the appendix gives it (docs/validation.md 'Readings')"},
      {"vehicle.flexible_drop.bogie_bounce", "leading-bogie bounce (its lowest mode)", rigid.bogie_first_hz,
       clm.bogie_first_hz, wink.bogie_first_hz, Verdict::Agrees, ""},
      {"vehicle.flexible_drop.bogie_pitch", "leading-bogie pure pitch", rigid.bogie_pitch_hz, clm.bogie_pitch_hz,
       wink.bogie_pitch_hz, Verdict::Differs,
       "this ~90 Hz pure pitch is not the paper's 22-24 Hz mode (vehicle.bogie_pure_pitch) and drops 4 %; the 22 Hz "
       "mode of vehicle.bogie_pitch_about_motor_axle drops 11 % (Winkler)"},
  };
  for (const Drop& d : drops) {
    const double drop_clm = 1.0 - d.clm_hz / d.rigid_hz, drop_wink = 1.0 - d.wink_hz / d.rigid_hz;
    Claim c = claim(d.id, "vehicle",
                    std::string("track flexibility lowers f0 of the first three modes by 5-20 % (Table 1): ") + d.what,
                    "decrease rigid -> flexible in [5, 20] % on the CLM or the Winkler track");
    c.ours = fixed(d.rigid_hz, 2) + " -> " + fixed(d.clm_hz, 2) + " Hz CLM (" + fixed(100 * drop_clm, 1) + " %), " +
             fixed(d.wink_hz, 2) + " Hz Winkler (" + fixed(100 * drop_wink, 1) + " %)";
    auto in = [](double x) { return x >= 0.05 && x <= 0.20; };
    c.verdict = verdictOf(in(drop_clm) || in(drop_wink));
    c.expected = d.expected;
    c.command = modes_cmd + " [--foundation winkler]";
    c.cause = d.cause;
    out.push_back(c);
  }
}

// ------------------------------------------------------------------ impedance
void impedanceClaims(const Config& cfg, std::vector<Claim>& out) {
  const vehicle::VehicleModel model(vehicle::loadVehicleParams(cfg.root(), "t2000"));
  const track::TrackParams tp = track::loadTrackParams(cfg.root());
  std::vector<double> f;
  for (int k = 0; k < 120; ++k) f.push_back(2.0 * std::pow(100.0 / 2.0, k / 119.0));
  for (int wheel : {0, 1}) {
    const auto zr = vehicle::wheelImpedanceRigid(model, wheel, f);
    const auto zf = vehicle::wheelImpedanceFlexible(model, tp, wheel, f);
    double log_ratio = 0.0;
    int n = 0, extrema = 0;
    for (size_t k = 0; k < f.size(); ++k) {
      if (f[k] > 50.0) continue;
      log_ratio += std::log10(std::abs(zf[k]) / std::abs(zr[k]));
      ++n;
    }
    for (size_t k = 1; k + 1 < f.size(); ++k) {
      if (f[k] > 70.0) break;
      const double a = std::abs(zf[k - 1]), b = std::abs(zf[k]), c = std::abs(zf[k + 1]);
      if ((b > a && b > c) || (b < a && b < c)) ++extrema;
    }
    const double mean_ratio = std::pow(10.0, log_ratio / n);
    Claim c =
        claim(std::string("impedance.flexible_lower.wheel") + std::to_string(wheel), "impedance",
              wheel == 0 ? "with a flexible track the motor wheel impedances decrease in level, with variations around "
                           "vehicle natural frequencies up to 70 Hz (Fig. 10)"
                         : "similar results with the trailer wheels (section 3.2)",
              "|Z| flexible / rigid, geometric mean over 2-50 Hz, below 1/3; at least two extrema of |Z| flexible "
              "below 70 Hz");
    c.ours = "mean ratio " + fixed(mean_ratio, 3) + ", " + std::to_string(extrema) + " extrema below 70 Hz";
    c.verdict = verdictOf(mean_ratio < 1.0 / 3.0 && extrema >= 2);
    c.expected = Verdict::Agrees;
    c.command = std::string("railvib_tool wheel-impedance ") + kConfig + " --wheel " + std::to_string(wheel) +
                " --track rigid|flexible --csv z.csv";
    out.push_back(c);
  }
}

// ------------------------------------------------------------------ defect
void defectClaims(const Config& cfg, std::vector<Claim>& out) {
  const vehicle::UnevennessParams up = vehicle::loadUnevennessParams(cfg.root());
  const vehicle::PassageParams pp = vehicle::loadPassageParams(cfg.root());
  const double R = vehicle::loadVehicleParams(cfg.root(), "t2000").wheels.front().radius_m;
  // |Z(f)| of the wheel/profile contact height z(x) as the wheel sees it at speed V: f = V / wavelength
  const double dx = 1e-5, x0 = up.defect.position_m - 0.05, x1 = up.defect.position_m + 0.06;
  auto spectrum = [&](double f_hz) {
    const double kx = 2.0 * M_PI * f_hz / pp.speed_m_s;
    std::complex<double> s = 0.0;
    for (double x = x0; x <= x1; x += dx)
      s += vehicle::defectEnvelope(x, up.defect, R) * std::exp(std::complex<double>(0.0, -kx * x)) * dx;
    return std::abs(s);
  };
  const double z0 = spectrum(1.0);
  double f3 = 0.0;
  for (double f = 1.0; f <= 400.0; f += 1.0) {
    if (spectrum(f) < z0 / std::sqrt(2.0)) {
      f3 = f;
      break;
    }
  }
  Claim c =
      claim("defect.flat_spectrum", "defect",
            "with this defect at low speed, frequencies up to around 50 Hz are equally excited (section 3.1, Fig. 7b)",
            "the contact-height spectrum at 30 km/h stays within 3 dB of its low-frequency value up to >= 45 Hz");
  c.ours = "-3 dB at " + fixed(f3, 0) + " Hz (8 m^-1 at " + fixed(pp.speed_m_s * 3.6, 0) +
           " km/h: " + fixed(8.0 * pp.speed_m_s, 1) + " Hz, the paper's 'about 70 Hz')";
  c.verdict = verdictOf(f3 >= 45.0);
  c.expected = Verdict::Agrees;
  c.command = "railvib_tool validate (defect.flat_spectrum)";
  out.push_back(c);
}

// ------------------------------------------------------------------ passage
void passageClaims(const Config& cfg, std::vector<Claim>& out) {
  const Config run_cfg =
      Config::load(cfg.file(), {"vehicle.name=t2000", "simulation.duration_s=3.6", "simulation.time_step_s=2.0e-5"});
  const vehicle::VehicleModel model(vehicle::loadVehicleParams(run_cfg.root()));
  const vehicle::PassageParams pp = vehicle::loadPassageParams(run_cfg.root());
  const track::TrackParams tp = track::loadTrackParams(run_cfg.root());
  const vehicle::Unevenness unev(vehicle::loadUnevennessParams(run_cfg.root()), tp.layout.x_min_m, tp.layout.x_max_m);
  vehicle::VehiclePassage run(model, unev, pp, vehicle::makeRailSupport(pp, tp));
  const int nw = model.wheelCount();
  std::vector<double> peak(nw, 0.0), t_peak(nw, 0.0);
  vehicle::PassageBlock block;
  while (!run.finished()) {
    run.advance(8192, block);
    for (size_t k = 0; k < block.sampleCount(); ++k) {
      for (int i = 0; i < nw; ++i) {
        if (block.contact_force_n[k * nw + i] > peak[i]) {
          peak[i] = block.contact_force_n[k * nw + i];
          t_peak[i] = block.time_s[k];
        }
      }
    }
  }
  const double paper[6] = {1.4, 1.6, 2.3, 2.5, 3.2, 3.4};
  double worst = 0.0;
  std::string times;
  for (int i = 0; i < nw && i < 6; ++i) {
    worst = std::max(worst, std::abs(t_peak[i] - paper[i]));
    times += (times.empty() ? "" : ", ") + fixed(t_peak[i], 3);
  }
  double peak_max = *std::max_element(peak.begin(), peak.end());
  Claim c = claim("passage.impact_times", "passage",
                  "each axle crosses the defect at t = 1.4, 1.6, 2.3, 2.5, 3.2 and 3.4 s (section 3.5)",
                  "time of each wheel's largest contact force within 10 ms of the paper's");
  c.ours = times + " s (largest contact force " + fixed(peak_max / 1e3, 1) + " kN)";
  c.verdict = verdictOf(worst <= 0.010);
  c.expected = Verdict::Agrees;
  c.command = std::string("railvib_tool passage ") + kConfig + " --out DIR --duration 3.6";
  out.push_back(c);
}

// ------------------------------------------------------------------ building
void buildingClaims(const Config& cfg, const ValidationOptions& opt, std::vector<Claim>& out) {
  const building::BuildingModel house(building::loadBuildingParams(cfg.root()));
  const building::ModalResult modes = building::modalAnalysis(house);
  const std::string cmd = std::string("railvib_tool building-modes ") + kConfig;
  const building::BuildingParams& hp = house.params();
  const building::Mode* upper_floor_bending = building::upperFloorBending(modes, hp);
  // The doubly symmetric modes as computed (with or without the roof slab), not a recorded list.
  int symmetric = 0;
  std::string symmetric_list;
  for (const auto& m : modes.modes) {
    if (!m.symmetric) continue;
    ++symmetric;
    symmetric_list += (symmetric_list.empty() ? "" : ", ") + m.label + " " + fixed(m.frequency_hz, 1) + " Hz";
  }
  {
    const double f = upper_floor_bending ? upper_floor_bending->frequency_hz : 0.0;
    Claim c = claim("building.first_floor_bending", "building",
                    "first vertical bending of the upper floor at 15.0 Hz (section 3.4, Fig. 13)",
                    "lowest doubly symmetric fixed-base mode in which the upper floor bends most, within 5 % of "
                    "15.0 Hz");
    c.ours = fixed(f, 2) + " Hz (" + (upper_floor_bending ? upper_floor_bending->label : std::string("none")) + ")";
    c.verdict = verdictOf(std::abs(f / 15.0 - 1.0) <= 0.05);
    // Measured (docs/validation.md): 14.36 Hz with the roof slab, 12.64 Hz with a free top edge.
    c.expected = hp.roof_slab ? Verdict::Agrees : Verdict::Differs;
    c.command = cmd;
    c.cause =
        "the floor's fundamental lies between its simply supported (8.3 Hz) and clamped (~16 Hz) bounds: it is "
        "set by the restraint the walls give the floor edges; " +
        std::string(hp.roof_slab ? "the roof slab holds the walls' tops"
                                 : "our walls have a free top edge (building.roof_slab: false), which restrains "
                                   "the floor less than a roof-held wall") +
        "; mesh-converged and within 0.4 % of CalculiX (docs/building.md)";
    out.push_back(c);
  }
  {
    Claim c = claim("building.only_symmetric_mode", "building",
                    "only the mode at 15.0 Hz can be defined as symmetric (section 3.4)",
                    "exactly one doubly symmetric fixed-base mode in 0-50 Hz");
    c.ours = std::to_string(symmetric) + " doubly symmetric modes in 0-50 Hz";
    c.verdict = verdictOf(symmetric == 1);
    c.expected = Verdict::Differs;
    c.command = cmd;
    c.cause = std::string(hp.roof_slab ? "with the roof slab" : "our walls have a free top edge (no roof)") +
              ": the doubly symmetric modes below 50 Hz are " + symmetric_list +
              "; the paper shows half of a symmetric model and names only the floor mode";
    out.push_back(c);
  }
  {
    double err_23 = 1e9, err_27 = 1e9, f23 = 0.0, f27 = 0.0;
    for (const auto& m : modes.modes) {
      if (std::abs(m.frequency_hz / 23.8 - 1.0) < err_23)
        err_23 = std::abs(m.frequency_hz / 23.8 - 1.0), f23 = m.frequency_hz;
      if (std::abs(m.frequency_hz / 27.0 - 1.0) < err_27)
        err_27 = std::abs(m.frequency_hz / 27.0 - 1.0), f27 = m.frequency_hz;
    }
    Claim c = claim("building.secondary_modes", "building",
                    "secondary bending modes at 23.8 and 27.0 Hz, wall flexure 25-30 Hz (section 3.4)",
                    "a fixed-base mode within 5 % of each of 23.8 and 27.0 Hz");
    c.ours = fixed(f23, 2) + " and " + fixed(f27, 2) + " Hz";
    c.verdict = verdictOf(err_23 <= 0.05 && err_27 <= 0.05);
    c.expected = Verdict::Agrees;
    c.command = cmd;
    out.push_back(c);
  }
  if (opt.quick) return;
  const building::TransferFunctions tf = building::impulseTransferFunctions(house);
  const std::string tf_cmd = std::string("railvib_tool building-tf ") + kConfig + " --csv tf.csv";
  auto column = [&](const std::string& name) {
    for (size_t p = 0; p < tf.names.size(); ++p) {
      if (tf.names[p] == name) return static_cast<int>(p);
    }
    return -1;
  };
  const int ground = column("ground_floor"), first = column("first_floor");
  if (ground >= 0) {
    double worst = 0.0;
    for (size_t j = 1; j < tf.frequency_hz.size(); ++j) {
      if (tf.frequency_hz[j] <= 50.0) worst = std::max(worst, std::abs(std::abs(tf.tf(j, ground)) - 1.0));
    }
    Claim c = claim("building.ground_floor_tf", "building",
                    "the ground floor has no significant resonance in the analysed range (section 3.4, Fig. 14)",
                    "|TF| of the ground floor within 20 % of 1 up to 50 Hz");
    c.ours = "max | |TF| - 1 | = " + fixed(worst, 3);
    c.verdict = verdictOf(worst <= 0.2);
    c.expected = Verdict::Agrees;
    c.command = tf_cmd;
    out.push_back(c);
  }
  if (first >= 0) {
    std::vector<double> peaks;
    for (size_t j = 1; j + 1 < tf.frequency_hz.size(); ++j) {
      const double a = std::abs(tf.tf(j, first));
      if (a <= 2.0 || tf.frequency_hz[j] > 50.0) continue;
      bool is_peak = true;
      for (size_t k = 0; k < tf.frequency_hz.size() && is_peak; ++k) {
        if (k != j && std::abs(tf.frequency_hz[k] - tf.frequency_hz[j]) <= 1.0 && std::abs(tf.tf(k, first)) > a)
          is_peak = false;
      }
      if (is_peak) peaks.push_back(tf.frequency_hz[j]);
    }
    auto near = [&](double target, double tol) {
      for (double p : peaks) {
        if (std::abs(p - target) <= tol) return true;
      }
      return false;
    };
    std::string list;
    for (double p : peaks) list += (list.empty() ? "" : ", ") + fixed(p, 1);
    {
      Claim c = claim("building.first_floor_tf_peaks", "building",
                      "the first floor presents two well-marked peaks, around 15 and 25 Hz (section 3.4, Fig. 14)",
                      "TF peaks (|TF| > 2) within 2 Hz of 15 Hz and of 25 Hz");
      c.ours = "peaks at " + list + " Hz";
      c.verdict = verdictOf(near(15.0, 2.0) && near(25.0, 2.0));
      c.expected = Verdict::Differs;
      c.command = tf_cmd;
      // The modes named here are those computed, with or without the roof slab.
      std::string near_25;
      double near_25_err = 1e9;
      for (const auto& m : modes.modes) {
        if (!m.symmetric && std::abs(m.frequency_hz - 25.0) < near_25_err) {
          near_25_err = std::abs(m.frequency_hz - 25.0);
          near_25 = m.label + " " + fixed(m.frequency_hz, 1) + " Hz";
        }
      }
      c.cause =
          "a uniform vertical foundation motion of a symmetric house excites only its doubly symmetric "
          "modes (" +
          symmetric_list + "); the mode nearest 25 Hz (" + near_25 +
          ") is antisymmetric and has no participation under uniform excitation";
      out.push_back(c);
    }
    {
      double worst = 0.0;
      for (double p : peaks) {
        double best = 1e9;
        for (const auto& m : modes.modes) best = std::min(best, std::abs(m.frequency_hz - p));
        worst = std::max(worst, best);
      }
      Claim c =
          claim("building.fixed_base_modes_suffice", "building",
                "a modal analysis of the building with a fixed foundation is sufficient to estimate the upper floor "
                "modes (section 3.4)",
                "every first-floor TF peak within 0.5 Hz of a fixed-base mode");
      c.ours = "largest distance " + fixed(worst, 2) + " Hz";
      c.verdict = verdictOf(!peaks.empty() && worst <= 0.5);
      c.expected = Verdict::Agrees;
      c.command = tf_cmd;
      out.push_back(c);
    }
  }
}

}  // namespace

std::vector<Claim> modelClaims(const Config& cfg, const ValidationOptions& opt) {
  std::vector<Claim> out;
  trackClaims(cfg, out);
  rigorousTrackClaims(cfg, opt, out);
  vehicleClaims(cfg, out);
  impedanceClaims(cfg, out);
  defectClaims(cfg, out);
  if (!opt.quick) passageClaims(cfg, out);
  buildingClaims(cfg, opt, out);
  return out;
}

}  // namespace railvib::validation
