// railvib/signal: one-stop vibration monitor of a velocity sensor (the
// virtual sensor node's metrics, live) and the same evaluation over a whole
// record (report, railvib_tool metrics, offline checks of the live values).
//
// Input: C velocity components in m/s, frame-interleaved, at fs. Per
// component: KB_F(t) and KB_Fmax (DIN 4150-2, velocity converted to mm/s),
// PPV with its zero-crossing dominant frequency and the DIN 4150-3
// residential guideline, running and equivalent one-third-octave levels.
#pragma once

#include <string>
#include <vector>

#include "railvib/signal/third_octave.hpp"
#include "railvib/signal/vibration.hpp"

namespace railvib::signal {

struct MonitorSpec {
  double fs_hz = 1000.0;
  size_t components = 3;
  KbSpec kb{};
  double third_octave_min_hz = 1.0;    ///< nominal
  double third_octave_max_hz = 100.0;  ///< nominal (bands above 0.45 fs are dropped)
  double third_octave_tau_s = 1.0;     ///< running levels ("Slow")
  double v_ref_m_s = kVelocityRefIso1683;
};

struct MonitorSnapshot {
  double time_s = 0.0;          ///< time of the last processed sample (from the first)
  std::vector<double> kb_f;     ///< per component, current KB_F
  std::vector<double> kb_fmax;  ///< per component, max since start
  double kb_fmax_all = 0.0;     ///< max over components (DIN 4150-2 uses the largest)
  PpvEvaluation ppv;            ///< per component + vector sum, DIN 4150-3
  std::vector<ThirdOctaveBand> bands;
  std::vector<std::vector<double>> third_octave_running_db;     ///< [component][band]
  std::vector<std::vector<double>> third_octave_equivalent_db;  ///< [component][band] since start
};

class VibrationMonitor {
 public:
  explicit VibrationMonitor(const MonitorSpec& spec);
  /// Push frames of velocity (m/s); kb_f_out (may be null) receives KB_F per frame and component (interleaved).
  void process(const double* velocity_m_s, size_t frames, double* kb_f_out = nullptr);
  MonitorSnapshot snapshot() const;
  const MonitorSpec& spec() const { return spec_; }
  uint64_t sampleCount() const { return n_; }

 private:
  MonitorSpec spec_;
  std::vector<KbWeighting> kb_;
  PpvEvaluator ppv_;
  std::vector<ThirdOctaveAnalyzer> octave_;
  std::vector<double> frame_mm_s_;
  uint64_t n_ = 0;
};

struct RecordMetrics {
  MonitorSnapshot summary;                ///< at the end of the record
  std::vector<std::vector<double>> kb_f;  ///< [component][sample]
  std::vector<double> spectral_peak_hz;   ///< per component, largest amplitude-spectrum line >= 1 Hz
  std::vector<double> kb_ftm;             ///< per component, 30 s cycles
};

/// Offline: the monitor over a whole record; components[c][i] in m/s.
RecordMetrics evaluateRecord(const std::vector<std::vector<double>>& components_m_s, const MonitorSpec& spec);

/// The verdicts of one sensor's metrics where it stands (SensorKind): DIN 4150-2 on KB_Fmax (people in
/// buildings: foundation and floor sensors) and DIN 4150-3 (structures: the foundation curve, the floor
/// values); in the free field neither applies (NotApplicable, the figures kept for information). A
/// verdict whose governing frequency (the peak's dominant frequency of the component that governs it:
/// the largest KB_Fmax, the largest PPV / guideline) lies above resolved_hz, the highest frequency the
/// model resolves (soil.mesh.f_max_hz; infinity for a measured record), is NotAssessable. The sensor's
/// level is DIN 4150-2's, raised to Error when DIN 4150-3 is not met; DIN 4150-3's when DIN 4150-2 cannot
/// be judged; NotApplicable in the free field; NotAssessable when neither can be judged.
struct SensorVerdict {
  VerdictLevel level = VerdictLevel::Ok;
  std::string reason;
  Din4150_2Verdict din4150_2;
  Din4150_3Verdict din4150_3;
  double din4150_2_frequency_hz = 0.0;  ///< governing frequency of DIN 4150-2's judgement
};
/// kb_ftr: the DIN 4150-2 rating if known (offline, with an exposure time), else none (live).
SensorVerdict sensorVerdict(const MonitorSnapshot& metrics, Din4150_2Period period, SensorKind kind, double resolved_hz,
                            std::optional<double> kb_ftr = std::nullopt);

}  // namespace railvib::signal
