// railvib/signal: vibration metrics of buildings and ground.
//
//  - DIN 4150-2 / DIN 45669-1 KB weighting, running rms KB_F(t) (tau = 0.125 s)
//    and KB_Fmax; DIN 4150-2 guide values A_u / A_o / A_r and verdict.
//  - Peak particle velocity per component and vector sum, dominant frequency
//    of the peak (zero-crossing half period), DIN 4150-3 short-term guideline
//    for residential buildings at the foundation and verdict.
// Every class streams (sample by sample or by block) so nodes use it live;
// the offline helpers run the same code over a whole record.
#pragma once

#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "railvib/signal/filter_design.hpp"

namespace railvib::signal {

// ------------------------------------------------------------------ KB weighting

struct KbSpec {
  double highpass_hz = 0.8;   ///< band limit, 2-pole Butterworth high pass
  double lowpass_hz = 100.0;  ///< band limit, 2-pole Butterworth low pass
  /// Bilinear matching frequency of the low pass (exact analog magnitude there):
  /// the top of the 1-80 Hz building range, so a 1 kHz stream stays accurate.
  double lowpass_match_hz = 80.0;
  double f0_hz = 5.6;    ///< H_KB = 1 / (1 - i f0 / f), a first-order high pass
  double tau_s = 0.125;  ///< time constant of the running rms ("F")
};

/// KB evaluation of one velocity component. Input velocity in mm/s (DIN
/// 4150-2 divides by v0 = 1 mm/s, so KB is dimensionless).
class KbWeighting {
 public:
  explicit KbWeighting(double fs_hz, const KbSpec& spec = {});

  /// One sample of velocity (mm/s); returns KB_F at that sample.
  double process(double velocity_mm_s);
  /// A block; kb_f_out (may be null) receives KB_F per sample.
  void process(const double* velocity_mm_s, size_t n, double* kb_f_out = nullptr);

  double kb() const { return kb_; }                      ///< last weighted sample KB(t)
  double kbF() const { return std::sqrt(y_); }           ///< last running rms KB_F(t)
  double kbFmax() const { return kb_fmax_; }             ///< max of KB_F since start / resetMax()
  double kbFmaxTime() const { return kb_fmax_time_s_; }  ///< time of KB_Fmax (s from the first sample)
  void resetMax() { kb_fmax_ = 0.0; }
  void reset();
  double sampleRate() const { return fs_; }
  const KbSpec& spec() const { return spec_; }

  /// Digital weighting (band limit * H_KB) at f.
  std::complex<double> response(double f_hz) const { return filter_.response(f_hz, fs_); }
  /// Analog reference weighting at f.
  static std::complex<double> analogResponse(double f_hz, const KbSpec& spec = {});

 private:
  double fs_;
  KbSpec spec_;
  BiquadCascade filter_;
  double alpha_, c0_, c1_;  // exact exponential average for KB^2 linear between samples
  double kb_ = 0.0, prev_sq_ = 0.0, y_ = 0.0;
  double kb_fmax_ = 0.0, kb_fmax_time_s_ = 0.0;
  uint64_t n_ = 0;
};

/// KB_F(t) of a whole record (velocity in mm/s).
std::vector<double> kbFSeries(const std::vector<double>& velocity_mm_s, double fs_hz, const KbSpec& spec = {});

/// DIN 4150-2 guide values (Anhaltswerte), Table 1.
struct Din4150_2GuideValues {
  double a_u;  ///< lower value
  double a_o;  ///< upper value
  double a_r;  ///< value for the rating level KB_FTr
};
enum class Din4150_2Period { Day, Night };
/// Residential areas ("allgemeine Wohngebiete", row 3): day 0.15 / 3 / 0.07, night 0.1 / 0.2 / 0.05.
Din4150_2GuideValues din4150_2Residential(Din4150_2Period period);

/// KB_FTm: quadratic mean of the maxima KB_FTi of consecutive 30 s cycles (Takt)
/// of a KB_F(t) series (a last incomplete cycle counts as a cycle).
double kbFTm(const std::vector<double>& kb_f, double fs_hz, double cycle_s = 30.0);
/// Rating value KB_FTr = KB_FTm * sqrt(T_e / T_r) (simplified: one exposure
/// class, no rest-period surcharge; T_r = 16 h day, 8 h night).
double kbFTr(double kb_ftm, double exposure_s, Din4150_2Period period);

/// Level of a verdict; the values are those of railvib/VibrationMetrics (VERDICT_OK, _WARN, _ERROR,
/// _NOT_APPLICABLE: the standard does not apply where the sensor stands, _NOT_ASSESSABLE: the metric's
/// governing frequency lies above the frequency the model resolves).
enum class VerdictLevel : uint8_t { Ok = 0, Warn = 1, Error = 2, NotApplicable = 3, NotAssessable = 4 };
std::string verdictName(VerdictLevel level);

/// Where a sensor stands, which decides what applies to it: DIN 4150-2 judges vibration where people
/// are, in buildings (foundation and floor sensors); DIN 4150-3 judges structures, at the foundation
/// (Table 1, column 2-4 curve) and on the floors (uppermost floor horizontal, floor slabs vertical).
/// In the free field neither applies: the metrics are for information. Values of VibrationMetrics KIND_*.
enum class SensorKind : uint8_t { FreeField = 0, Foundation = 1, Floor = 2 };
std::string sensorKindName(SensorKind kind);
/// "free_field" | "foundation" | "floor"; throws std::invalid_argument otherwise.
SensorKind sensorKindFromName(const std::string& name);

struct Din4150_2Verdict {
  bool met = false;
  /// Ok: met; Error: not met; Warn: A_u < KB_Fmax <= A_o and no KB_FTr given (the rating decides).
  VerdictLevel level = VerdictLevel::Error;
  std::string reason;
  Din4150_2GuideValues guide{};
  double kb_fmax = 0.0;
  double kb_ftr = 0.0;  ///< 0 when not given
};
/// DIN 4150-2 procedure (section 6.5.3): KB_Fmax <= A_u met; KB_Fmax > A_o not met; otherwise met
/// iff KB_FTr <= A_r. Without KB_FTr (a live sensor, whose exposure is not known yet) the middle
/// case is a warning: not met until a rating says otherwise.
Din4150_2Verdict din4150_2Verdict(double kb_fmax, std::optional<double> kb_ftr, Din4150_2Period period);

// ----------------------------------------------------------- PPV / DIN 4150-3

/// DIN 4150-3 Table 1 row 2 (residential buildings), short-term, at the
/// foundation: guideline PPV (mm/s) at dominant frequency f: 5 below 10 Hz,
/// 5 -> 15 over 10-50 Hz, 15 -> 20 over 50-100 Hz, 20 above.
double din4150_3ResidentialLimitMmS(double f_hz);
/// DIN 4150-3 on the floors of a residential building, short-term, at any frequency: 15 mm/s horizontal
/// (Table 1 row 2, the plane of the uppermost floor) and 20 mm/s vertical (floor slabs, section 5.1).
constexpr double kDin4150_3FloorHorizontalMmS = 15.0;
constexpr double kDin4150_3FloorVerticalMmS = 20.0;

/// Peak of |v| of one component with the dominant frequency of the half cycle
/// that holds it: f = 1 / (2 (t_zc2 - t_zc1)) between the zero crossings
/// (linearly interpolated) around the peak. Streaming.
class PeakTracker {
 public:
  explicit PeakTracker(double fs_hz);
  void process(double v);
  void process(const double* v, size_t n) {
    for (size_t i = 0; i < n; ++i) process(v[i]);
  }
  /// Peak |v| so far (units of the input).
  double peak() const { return best_peak_; }
  double peakTime() const { return best_time_s_; }
  /// Dominant frequency of the peak's half cycle (Hz). While the half cycle
  /// holding the peak is open, its duration so far is used: an upper bound of
  /// the final value (provisional() is true). 0 if no zero crossing seen yet.
  /// A slow drift or offset suppresses crossings and lowers f: the DIN 4150-3
  /// limit then errs on the safe (lower) side.
  double dominantFrequency() const;
  bool provisional() const { return best_open_; }
  void reset();

 private:
  double fs_;
  uint64_t n_ = 0;
  double prev_ = 0.0;
  double zc_time_s_ = -1.0;  // last zero crossing (s), -1 before the first
  double cur_peak_ = 0.0, cur_time_s_ = 0.0;
  double best_peak_ = 0.0, best_time_s_ = 0.0, best_zc_s_ = -1.0, best_half_s_ = 0.0;
  bool best_open_ = false;
};

/// Frequency of the largest amplitude-spectrum line (Hann window), Hz.
double spectralPeakFrequency(const std::vector<double>& x, double fs_hz, double f_min_hz = 1.0);

struct PpvComponent {
  double ppv_mm_s = 0.0;
  double time_s = 0.0;
  double frequency_hz = 0.0;  ///< zero-crossing dominant frequency of the peak
  double limit_mm_s = 0.0;    ///< DIN 4150-3 residential guideline at that frequency
  double ratio = 0.0;         ///< ppv / limit
};
struct PpvEvaluation {
  std::vector<PpvComponent> components;
  double vector_peak_mm_s = 0.0;  ///< max over t of |(vx, vy, vz)|
  double vector_peak_time_s = 0.0;
  double max_ratio = 0.0;  ///< max over components of ppv / limit(f)
  bool exceeded = false;   ///< max_ratio > 1
};

/// Live PPV / DIN 4150-3 evaluation of C components (mm/s), frame-interleaved input.
class PpvEvaluator {
 public:
  PpvEvaluator(double fs_hz, size_t components);
  void process(const double* interleaved_mm_s, size_t frames);
  PpvEvaluation evaluation() const;
  void reset();

 private:
  double fs_;
  std::vector<PeakTracker> trackers_;
  uint64_t n_ = 0;
  double vec_peak_ = 0.0, vec_time_s_ = 0.0;
};

/// Offline evaluation of component records (mm/s).
PpvEvaluation evaluatePpv(const std::vector<std::vector<double>>& components_mm_s, double fs_hz);

/// The component that governs DIN 4150-3 (each component's peak is judged against the guideline at
/// its own dominant frequency): the one with the largest ppv / limit. With three components (x, y,
/// z) the vertical one governs unless another is strictly closer to its limit; with fewer, the
/// first of the largest. 0 when there is no component.
size_t governingComponent(const PpvEvaluation& ppv);

struct Din4150_3Verdict {
  bool met = true;  ///< every component within its guideline (max ppv / limit <= 1)
  VerdictLevel level = VerdictLevel::Ok;
  size_t governing_component = 0;
  PpvComponent governing;  ///< its peak, dominant frequency and guideline
};
/// DIN 4150-3 Table 1 row 2 (residential building, short-term) at the foundation: each component
/// against the frequency-dependent curve.
Din4150_3Verdict din4150_3Verdict(const PpvEvaluation& ppv);
/// The components' guidelines (limit, ratio, max_ratio, exceeded) for a sensor of `kind`: the foundation
/// curve at the foundation and in the free field (for information), the floor values on a floor (x, y
/// horizontal, z vertical).
PpvEvaluation din4150_3ForKind(const PpvEvaluation& ppv, SensorKind kind);
/// DIN 4150-3 for a sensor of `kind` (din4150_3ForKind's guidelines); NotApplicable in the free field.
Din4150_3Verdict din4150_3Verdict(const PpvEvaluation& ppv, SensorKind kind);

}  // namespace railvib::signal
