// railvib/signal: live vibration monitor and record evaluation.
#include "railvib/signal/monitor.hpp"

#include <algorithm>
#include <stdexcept>

#include "railvib/signal/spectrum.hpp"

namespace railvib::signal {

VibrationMonitor::VibrationMonitor(const MonitorSpec& spec) : spec_(spec), ppv_(spec.fs_hz, spec.components) {
  if (spec.components == 0) throw std::invalid_argument("VibrationMonitor: at least one component");
  const auto bands = thirdOctaveBands(spec.third_octave_min_hz, spec.third_octave_max_hz, spec.fs_hz);
  for (size_t c = 0; c < spec.components; ++c) {
    kb_.emplace_back(spec.fs_hz, spec.kb);
    octave_.emplace_back(spec.fs_hz, bands, spec.third_octave_tau_s, spec.v_ref_m_s);
  }
  frame_mm_s_.resize(spec.components);
}

void VibrationMonitor::process(const double* v, size_t frames, double* kb_f_out) {
  const size_t nc = spec_.components;
  for (size_t i = 0; i < frames; ++i) {
    for (size_t c = 0; c < nc; ++c) {
      const double v_m_s = v[i * nc + c];
      frame_mm_s_[c] = 1e3 * v_m_s;
      const double kbf = kb_[c].process(frame_mm_s_[c]);
      if (kb_f_out) kb_f_out[i * nc + c] = kbf;
      octave_[c].process(v_m_s);
    }
    ppv_.process(frame_mm_s_.data(), 1);
    ++n_;
  }
}

MonitorSnapshot VibrationMonitor::snapshot() const {
  MonitorSnapshot s;
  s.time_s = n_ > 0 ? static_cast<double>(n_ - 1) / spec_.fs_hz : 0.0;
  for (const auto& k : kb_) {
    s.kb_f.push_back(k.kbF());
    s.kb_fmax.push_back(k.kbFmax());
    s.kb_fmax_all = std::max(s.kb_fmax_all, k.kbFmax());
  }
  s.ppv = ppv_.evaluation();
  s.bands = octave_.front().bands();
  for (const auto& o : octave_) {
    s.third_octave_running_db.push_back(o.runningLevelsDb());
    s.third_octave_equivalent_db.push_back(o.equivalentLevelsDb());
  }
  return s;
}

RecordMetrics evaluateRecord(const std::vector<std::vector<double>>& components_m_s, const MonitorSpec& spec_in) {
  if (components_m_s.empty()) throw std::invalid_argument("evaluateRecord: no component");
  const size_t n = components_m_s.front().size();
  for (const auto& c : components_m_s) {
    if (c.size() != n) throw std::invalid_argument("evaluateRecord: components of different lengths");
  }
  MonitorSpec spec = spec_in;
  spec.components = components_m_s.size();
  const size_t nc = spec.components;
  VibrationMonitor m(spec);
  std::vector<double> frames(n * nc), kbf(n * nc);
  for (size_t i = 0; i < n; ++i) {
    for (size_t c = 0; c < nc; ++c) frames[i * nc + c] = components_m_s[c][i];
  }
  m.process(frames.data(), n, kbf.data());
  RecordMetrics r;
  r.summary = m.snapshot();
  r.kb_f.assign(nc, std::vector<double>(n));
  for (size_t i = 0; i < n; ++i) {
    for (size_t c = 0; c < nc; ++c) r.kb_f[c][i] = kbf[i * nc + c];
  }
  for (size_t c = 0; c < nc; ++c) {
    r.spectral_peak_hz.push_back(n >= 2 ? spectralPeakFrequency(components_m_s[c], spec.fs_hz) : 0.0);
    r.kb_ftm.push_back(kbFTm(r.kb_f[c], spec.fs_hz));
  }
  return r;
}

SensorVerdict sensorVerdict(const MonitorSnapshot& metrics, Din4150_2Period period, bool on_structure,
                            std::optional<double> kb_ftr) {
  SensorVerdict v;
  v.din4150_2 = din4150_2Verdict(metrics.kb_fmax_all, kb_ftr, period);
  v.din4150_3 = din4150_3Verdict(metrics.ppv);
  v.level = v.din4150_2.level;
  v.reason = v.level == VerdictLevel::Ok ? "within guide values" : "DIN 4150-2: " + v.din4150_2.reason;
  if (on_structure && !v.din4150_3.met) {
    v.level = VerdictLevel::Error;
    v.reason = "DIN 4150-3: PPV above the residential guideline";
  }
  return v;
}

}  // namespace railvib::signal
