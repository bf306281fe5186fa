// railvib/signal: live vibration monitor and record evaluation.
#include "railvib/signal/monitor.hpp"

#include <algorithm>
#include <sstream>
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

SensorVerdict sensorVerdict(const MonitorSnapshot& metrics, Din4150_2Period period, SensorKind kind, double resolved_hz,
                            std::optional<double> kb_ftr) {
  SensorVerdict v;
  v.din4150_2 = din4150_2Verdict(metrics.kb_fmax_all, kb_ftr, period);
  v.din4150_3 = din4150_3Verdict(metrics.ppv, kind);
  // DIN 4150-2's governing component: the largest KB_Fmax; its frequency: that component's peak's.
  size_t kb_component = 0;
  for (size_t c = 1; c < metrics.kb_fmax.size(); ++c) {
    if (metrics.kb_fmax[c] > metrics.kb_fmax[kb_component]) kb_component = c;
  }
  if (kb_component < metrics.ppv.components.size()) {
    v.din4150_2_frequency_hz = metrics.ppv.components[kb_component].frequency_hz;
  }
  if (kind == SensorKind::FreeField) {
    v.din4150_2.level = VerdictLevel::NotApplicable;
    v.level = VerdictLevel::NotApplicable;
    v.reason =
        "free field: DIN 4150-2 (people in buildings) and DIN 4150-3 (structures) do not apply; the metrics "
        "are for information";
    return v;
  }
  const auto above = [resolved_hz](double f_hz) { return f_hz > resolved_hz; };
  std::ostringstream unresolved;
  if (above(v.din4150_2_frequency_hz)) {
    v.din4150_2.level = VerdictLevel::NotAssessable;
    unresolved << "DIN 4150-2 not assessable: its governing frequency " << v.din4150_2_frequency_hz
               << " Hz lies above the resolved " << resolved_hz << " Hz";
  }
  if (above(v.din4150_3.governing.frequency_hz)) {
    v.din4150_3.level = VerdictLevel::NotAssessable;
    unresolved << (unresolved.tellp() > 0 ? "; " : "") << "DIN 4150-3 not assessable: its governing frequency "
               << v.din4150_3.governing.frequency_hz << " Hz lies above the resolved " << resolved_hz << " Hz";
  }
  const bool judged_2 = v.din4150_2.level != VerdictLevel::NotAssessable;
  const bool judged_3 = v.din4150_3.level != VerdictLevel::NotAssessable;
  if (judged_2) {
    v.level = v.din4150_2.level;
    v.reason = v.level == VerdictLevel::Ok ? "within guide values" : "DIN 4150-2: " + v.din4150_2.reason;
  } else if (judged_3) {
    v.level = v.din4150_3.level;
    v.reason = v.din4150_3.met ? "DIN 4150-3 within its guideline" : "";
  } else {
    v.level = VerdictLevel::NotAssessable;
  }
  if (judged_3 && !v.din4150_3.met) {
    v.level = VerdictLevel::Error;
    v.reason = kind == SensorKind::Floor ? "DIN 4150-3: PPV above the floor guideline"
                                         : "DIN 4150-3: PPV above the residential guideline";
  }
  if (unresolved.tellp() > 0) v.reason += (v.reason.empty() ? "" : "; ") + unresolved.str();
  return v;
}

}  // namespace railvib::signal
