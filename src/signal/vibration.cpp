// railvib/signal: KB weighting (DIN 4150-2 / DIN 45669-1), PPV and DIN 4150-3.
#include "railvib/signal/vibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "railvib/common/constants.hpp"
#include "railvib/signal/spectrum.hpp"

namespace railvib::signal {

// ------------------------------------------------------------------ KB weighting

KbWeighting::KbWeighting(double fs_hz, const KbSpec& spec) : fs_(fs_hz), spec_(spec) {
  if (!(fs_hz > 2.0 * spec.lowpass_hz) || !(fs_hz > 2.0 * spec.lowpass_match_hz)) {
    throw std::invalid_argument("KbWeighting: sample rate " + std::to_string(fs_hz) +
                                " Hz too low (needs > 2 x the 100 Hz band limit; >= 500 Hz recommended)");
  }
  if (!(spec.tau_s > 0.0) || !(spec.f0_hz > 0.0) || !(spec.highpass_hz > 0.0)) {
    throw std::invalid_argument("KbWeighting: tau, f0 and band limits must be positive");
  }
  filter_ = butterworthHighpass(2, spec.highpass_hz, fs_hz);
  filter_.append(butterworthLowpass(2, spec.lowpass_hz, fs_hz, spec.lowpass_match_hz));
  filter_.append(firstOrderHighpass(spec.f0_hz, fs_hz));
  // dY/dt = (KB^2 - Y) / tau integrated exactly for KB^2 linear between samples.
  const double x = 1.0 / (fs_hz * spec.tau_s);
  alpha_ = std::exp(-x);
  c0_ = (1.0 - alpha_) / x - alpha_;
  c1_ = 1.0 - (1.0 - alpha_) / x;
}

void KbWeighting::reset() {
  filter_.reset();
  kb_ = prev_sq_ = y_ = 0.0;
  kb_fmax_ = kb_fmax_time_s_ = 0.0;
  n_ = 0;
}

double KbWeighting::process(double velocity_mm_s) {
  kb_ = filter_.process(velocity_mm_s);
  const double sq = kb_ * kb_;
  y_ = alpha_ * y_ + c0_ * prev_sq_ + c1_ * sq;
  prev_sq_ = sq;
  const double kbf = std::sqrt(std::max(y_, 0.0));
  if (kbf > kb_fmax_) {
    kb_fmax_ = kbf;
    kb_fmax_time_s_ = static_cast<double>(n_) / fs_;
  }
  ++n_;
  return kbf;
}

void KbWeighting::process(const double* velocity_mm_s, size_t n, double* kb_f_out) {
  for (size_t i = 0; i < n; ++i) {
    const double v = process(velocity_mm_s[i]);
    if (kb_f_out) kb_f_out[i] = v;
  }
}

std::complex<double> KbWeighting::analogResponse(double f_hz, const KbSpec& spec) {
  const std::complex<double> s(0.0, 2.0 * kPi * f_hz);
  const double wh = 2.0 * kPi * spec.highpass_hz;
  const double wl = 2.0 * kPi * spec.lowpass_hz;
  const double w0 = 2.0 * kPi * spec.f0_hz;
  const double r2 = std::sqrt(2.0);
  return s * s / (s * s + r2 * wh * s + wh * wh) * (wl * wl) / (s * s + r2 * wl * s + wl * wl) * s / (s + w0);
}

std::vector<double> kbFSeries(const std::vector<double>& velocity_mm_s, double fs_hz, const KbSpec& spec) {
  KbWeighting kb(fs_hz, spec);
  std::vector<double> out(velocity_mm_s.size());
  kb.process(velocity_mm_s.data(), velocity_mm_s.size(), out.data());
  return out;
}

Din4150_2GuideValues din4150_2Residential(Din4150_2Period period) {
  return period == Din4150_2Period::Day ? Din4150_2GuideValues{0.15, 3.0, 0.07} : Din4150_2GuideValues{0.1, 0.2, 0.05};
}

double kbFTm(const std::vector<double>& kb_f, double fs_hz, double cycle_s) {
  if (kb_f.empty()) return 0.0;
  const size_t m = std::max<size_t>(1, static_cast<size_t>(std::llround(cycle_s * fs_hz)));
  double sum = 0.0;
  size_t cycles = 0;
  for (size_t start = 0; start < kb_f.size(); start += m) {
    const size_t end = std::min(kb_f.size(), start + m);
    const double mx = *std::max_element(kb_f.begin() + static_cast<std::ptrdiff_t>(start),
                                        kb_f.begin() + static_cast<std::ptrdiff_t>(end));
    sum += mx * mx;
    ++cycles;
  }
  return std::sqrt(sum / static_cast<double>(cycles));
}

double kbFTr(double kb_ftm, double exposure_s, Din4150_2Period period) {
  const double tr = (period == Din4150_2Period::Day ? 16.0 : 8.0) * 3600.0;
  return kb_ftm * std::sqrt(std::clamp(exposure_s, 0.0, tr) / tr);
}

Din4150_2Verdict din4150_2Verdict(double kb_fmax, std::optional<double> kb_ftr, Din4150_2Period period) {
  Din4150_2Verdict v;
  v.guide = din4150_2Residential(period);
  v.kb_fmax = kb_fmax;
  v.kb_ftr = kb_ftr.value_or(0.0);
  auto decide = [&v](bool met, const char* reason) {
    v.met = met;
    v.level = met ? VerdictLevel::Ok : VerdictLevel::Error;
    v.reason = reason;
  };
  if (kb_fmax <= v.guide.a_u) {
    decide(true, "KB_Fmax <= A_u");
  } else if (kb_fmax > v.guide.a_o) {
    decide(false, "KB_Fmax > A_o");
  } else if (!kb_ftr) {
    decide(false, "A_u < KB_Fmax <= A_o: the rating KB_FTr decides");
    v.level = VerdictLevel::Warn;
  } else if (*kb_ftr <= v.guide.a_r) {
    decide(true, "A_u < KB_Fmax <= A_o and KB_FTr <= A_r");
  } else {
    decide(false, "A_u < KB_Fmax <= A_o and KB_FTr > A_r");
  }
  return v;
}

// ----------------------------------------------------------- PPV / DIN 4150-3

double din4150_3ResidentialLimitMmS(double f_hz) {
  if (f_hz < 10.0) return 5.0;
  if (f_hz <= 50.0) return 5.0 + (f_hz - 10.0) * (10.0 / 40.0);
  if (f_hz <= 100.0) return 15.0 + (f_hz - 50.0) * (5.0 / 50.0);
  return 20.0;
}

PeakTracker::PeakTracker(double fs_hz) : fs_(fs_hz) {
  if (!(fs_hz > 0.0)) throw std::invalid_argument("PeakTracker: sample rate must be > 0");
}

void PeakTracker::reset() { *this = PeakTracker(fs_); }

void PeakTracker::process(double v) {
  const double t = static_cast<double>(n_) / fs_;
  if (n_ > 0 && ((prev_ < 0.0 && v >= 0.0) || (prev_ > 0.0 && v <= 0.0))) {
    const double tz = t - (v / (v - prev_)) / fs_;
    if (best_open_) {
      best_open_ = false;
      best_half_s_ = best_zc_s_ >= 0.0 ? tz - best_zc_s_ : 2.0 * (tz - best_time_s_);
    }
    zc_time_s_ = tz;
    cur_peak_ = 0.0;
  }
  const double a = std::abs(v);
  if (a > cur_peak_) {
    cur_peak_ = a;
    cur_time_s_ = t;
  }
  if (a > best_peak_) {
    best_peak_ = a;
    best_time_s_ = t;
    best_zc_s_ = zc_time_s_;
    best_open_ = true;
    best_half_s_ = best_zc_s_ >= 0.0 ? t - best_zc_s_ : 0.0;
  } else if (best_open_ && best_zc_s_ >= 0.0) {
    best_half_s_ = t - best_zc_s_;
  }
  prev_ = v;
  ++n_;
}

double PeakTracker::dominantFrequency() const { return best_half_s_ > 0.0 ? 0.5 / best_half_s_ : 0.0; }

double spectralPeakFrequency(const std::vector<double>& x, double fs_hz, double f_min_hz) {
  const Spectrum s = amplitudeSpectrum(x, fs_hz, Window::Hann);
  double best = -1.0, f = 0.0;
  for (size_t k = 0; k < s.value.size(); ++k) {
    if (s.frequency_hz[k] >= f_min_hz && s.value[k] > best) {
      best = s.value[k];
      f = s.frequency_hz[k];
    }
  }
  return f;
}

PpvEvaluator::PpvEvaluator(double fs_hz, size_t components) : fs_(fs_hz), trackers_(components, PeakTracker(fs_hz)) {
  if (components == 0) throw std::invalid_argument("PpvEvaluator: at least one component");
}

void PpvEvaluator::reset() {
  for (auto& t : trackers_) t.reset();
  n_ = 0;
  vec_peak_ = vec_time_s_ = 0.0;
}

void PpvEvaluator::process(const double* x, size_t frames) {
  const size_t nc = trackers_.size();
  for (size_t i = 0; i < frames; ++i) {
    double sq = 0.0;
    for (size_t c = 0; c < nc; ++c) {
      const double v = x[i * nc + c];
      trackers_[c].process(v);
      sq += v * v;
    }
    const double mag = std::sqrt(sq);
    if (mag > vec_peak_) {
      vec_peak_ = mag;
      vec_time_s_ = static_cast<double>(n_) / fs_;
    }
    ++n_;
  }
}

PpvEvaluation PpvEvaluator::evaluation() const {
  PpvEvaluation e;
  for (const auto& t : trackers_) {
    PpvComponent c;
    c.ppv_mm_s = t.peak();
    c.time_s = t.peakTime();
    c.frequency_hz = t.dominantFrequency();
    c.limit_mm_s = din4150_3ResidentialLimitMmS(c.frequency_hz);
    c.ratio = c.ppv_mm_s / c.limit_mm_s;
    e.max_ratio = std::max(e.max_ratio, c.ratio);
    e.components.push_back(c);
  }
  e.vector_peak_mm_s = vec_peak_;
  e.vector_peak_time_s = vec_time_s_;
  e.exceeded = e.max_ratio > 1.0;
  return e;
}

PpvEvaluation evaluatePpv(const std::vector<std::vector<double>>& components_mm_s, double fs_hz) {
  if (components_mm_s.empty()) throw std::invalid_argument("evaluatePpv: no component");
  const size_t n = components_mm_s.front().size();
  for (const auto& c : components_mm_s) {
    if (c.size() != n) throw std::invalid_argument("evaluatePpv: components of different lengths");
  }
  const size_t nc = components_mm_s.size();
  PpvEvaluator ev(fs_hz, nc);
  std::vector<double> frame(nc);
  for (size_t i = 0; i < n; ++i) {
    for (size_t c = 0; c < nc; ++c) frame[c] = components_mm_s[c][i];
    ev.process(frame.data(), 1);
  }
  return ev.evaluation();
}

size_t governingComponent(const PpvEvaluation& ppv) {
  const auto& c = ppv.components;
  size_t worst = c.size() > 2 ? 2 : 0;
  for (size_t k = 0; k < c.size(); ++k) {
    if (c[k].ratio > c[worst].ratio) worst = k;
  }
  return worst;
}

std::string verdictName(VerdictLevel level) {
  switch (level) {
    case VerdictLevel::Ok:
      return "OK";
    case VerdictLevel::Warn:
      return "WARN";
    case VerdictLevel::Error:
      return "ERROR";
    case VerdictLevel::NotApplicable:
      return "not applicable";
    case VerdictLevel::NotAssessable:
      return "not assessable";
  }
  return "?";
}

std::string sensorKindName(SensorKind kind) {
  switch (kind) {
    case SensorKind::FreeField:
      return "free_field";
    case SensorKind::Foundation:
      return "foundation";
    case SensorKind::Floor:
      return "floor";
  }
  return "?";
}

SensorKind sensorKindFromName(const std::string& name) {
  if (name == "free_field") return SensorKind::FreeField;
  if (name == "foundation") return SensorKind::Foundation;
  if (name == "floor") return SensorKind::Floor;
  throw std::invalid_argument("unknown sensor kind '" + name + "' (free_field | foundation | floor)");
}

PpvEvaluation din4150_3ForKind(const PpvEvaluation& ppv, SensorKind kind) {
  if (kind != SensorKind::Floor) return ppv;
  PpvEvaluation floor = ppv;
  floor.max_ratio = 0.0;
  for (size_t c = 0; c < floor.components.size(); ++c) {
    PpvComponent& k = floor.components[c];
    k.limit_mm_s = c == 2 ? kDin4150_3FloorVerticalMmS : kDin4150_3FloorHorizontalMmS;
    k.ratio = k.ppv_mm_s / k.limit_mm_s;
    floor.max_ratio = std::max(floor.max_ratio, k.ratio);
  }
  floor.exceeded = floor.max_ratio > 1.0;
  return floor;
}

Din4150_3Verdict din4150_3Verdict(const PpvEvaluation& ppv, SensorKind kind) {
  Din4150_3Verdict v = din4150_3Verdict(din4150_3ForKind(ppv, kind));
  if (kind == SensorKind::FreeField) {
    v.met = true;
    v.level = VerdictLevel::NotApplicable;
  }
  return v;
}

Din4150_3Verdict din4150_3Verdict(const PpvEvaluation& ppv) {
  Din4150_3Verdict v;
  v.met = !ppv.exceeded;
  v.level = v.met ? VerdictLevel::Ok : VerdictLevel::Error;
  v.governing_component = governingComponent(ppv);
  if (v.governing_component < ppv.components.size()) v.governing = ppv.components[v.governing_component];
  return v;
}

}  // namespace railvib::signal
