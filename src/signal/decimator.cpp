// railvib/signal: streaming anti-alias decimator and stream interpolator.
#include "railvib/signal/decimator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "railvib/common/constants.hpp"
#include "railvib/signal/filter_design.hpp"

namespace railvib::signal {

namespace {

double sinc(double x) {
  if (std::abs(x) < 1e-12) return 1.0;
  const double px = kPi * x;
  return std::sin(px) / px;
}

// Kaiser window on [-1, 1] with shape beta.
double kaiser(double u, double beta) {
  if (std::abs(u) >= 1.0) return 0.0;
  return besselI0(beta * std::sqrt(1.0 - u * u)) / besselI0(beta);
}
}  // namespace

// ------------------------------------------------------------------ Decimator

namespace {
// Kaiser half width (s) for a transition of df Hz and attenuation a dB:
// N - 1 = (A - 7.95) / (2.285 * 2 pi df / fs)  =>  T = (A - 7.95) / (2 * 2.285 * 2 pi df).
double kaiserHalfWidth(double a, double df) { return (a - 7.95) / (2.0 * 2.285 * 2.0 * kPi * df); }

// Centred low-pass taps at rate fs, pass band edge fp, stop band edge fstop.
std::vector<double> designTaps(double fs, double fp, double fstop, double a, int64_t* half_out) {
  const double fc = 0.5 * (fp + fstop);
  const double beta = kaiserBeta(a);
  const int64_t d = static_cast<int64_t>(std::ceil(kaiserHalfWidth(a, fstop - fp) * fs));
  std::vector<double> taps(static_cast<size_t>(2 * d + 1));
  double sum = 0.0;
  for (int64_t j = -d; j <= d; ++j) {
    const double tau = static_cast<double>(j) / fs;
    const double h =
        2.0 * fc * sinc(2.0 * fc * tau) * kaiser(static_cast<double>(j) / (static_cast<double>(d) + 1.0), beta);
    taps[static_cast<size_t>(j + d)] = h;
    sum += h;
  }
  for (double& h : taps) h /= sum;
  *half_out = d;
  return taps;
}
}  // namespace

Decimator::Decimator(const DecimatorSpec& spec, size_t channels, double t0_s)
    : spec_(spec), channels_(channels), t0_(t0_s) {
  if (!(spec.input_rate_hz > 0.0) || !(spec.output_rate_hz > 0.0) || !std::isfinite(spec.input_rate_hz) ||
      !std::isfinite(spec.output_rate_hz)) {
    throw std::invalid_argument("Decimator: rates must be positive and finite");
  }
  if (spec.output_rate_hz > spec.input_rate_hz * (1.0 + 1e-12)) {
    throw std::invalid_argument("Decimator: output rate " + std::to_string(spec.output_rate_hz) +
                                " Hz exceeds input rate " + std::to_string(spec.input_rate_hz) +
                                " Hz (use StreamInterpolator to up-sample)");
  }
  if (!(spec.passband_fraction > 0.0 && spec.passband_fraction < 0.5)) {
    throw std::invalid_argument("Decimator: passband_fraction must be in (0, 0.5)");
  }
  if (!(spec.stopband_db >= 20.0 && spec.stopband_db <= 160.0)) {
    throw std::invalid_argument("Decimator: stopband_db must be in [20, 160]");
  }
  if (channels == 0) throw std::invalid_argument("Decimator: at least one channel");

  const double fi = spec.input_rate_hz;
  const double fo = spec.output_rate_hz;
  const double r = fi / fo;
  const double rr = std::round(r);
  if (std::abs(r - rr) < 1e-9 * r) ratio_ = static_cast<int>(rr);
  const double fp = spec.passband_fraction * fo;
  const double a = spec.stopband_db;

  if (ratio_ == 1) {
    FirStage st;
    st.taps = {1.0};
    stages_.push_back(st);
  } else if (ratio_ > 1) {
    // Choose one stage or a split M = M1 * M2 by the multiplications per input second.
    const double t2 = kaiserHalfWidth(a, 0.5 * fo - fp);
    double best_cost = (2.0 * std::ceil(t2 * fi) + 1.0) * fo;
    int best_m1 = 1;
    for (int m1 = 2; m1 < ratio_; ++m1) {
      if (ratio_ % m1 != 0) continue;
      const double f1 = fi / m1;           // stage-1 output rate
      const double stop1 = f1 - 0.5 * fo;  // what folds into [0, fo/2] must go
      if (!(stop1 > fp)) continue;
      const double cost =
          (2.0 * std::ceil(kaiserHalfWidth(a, stop1 - fp) * fi) + 1.0) * f1 + (2.0 * std::ceil(t2 * f1) + 1.0) * fo;
      if (cost < 0.8 * best_cost) {
        best_cost = cost;
        best_m1 = m1;
      }
    }
    if (best_m1 == 1) {
      FirStage st;
      st.ratio = ratio_;
      st.taps = designTaps(fi, fp, 0.5 * fo, a, &st.half);
      stages_.push_back(st);
    } else {
      // Two stages: their pass-band ripples add, so each is designed 6 dB deeper.
      FirStage s1, s2;
      s1.ratio = best_m1;
      s1.taps = designTaps(fi, fp, fi / best_m1 - 0.5 * fo, a + 6.0, &s1.half);
      s2.ratio = ratio_ / best_m1;
      s2.taps = designTaps(fi / best_m1, fp, 0.5 * fo, a + 6.0, &s2.half);
      stages_.push_back(s1);
      stages_.push_back(s2);
    }
    // Equivalent FIR at the input rate: h1 * (h2 up-sampled by M1), and the latency.
    taps_ = {1.0};
    int64_t up = 1;
    int64_t latency = 0;
    for (const FirStage& st : stages_) {
      std::vector<double> h(taps_.size() + static_cast<size_t>(up) * (st.taps.size() - 1), 0.0);
      for (size_t i = 0; i < taps_.size(); ++i) {
        for (size_t j = 0; j < st.taps.size(); ++j) h[i + static_cast<size_t>(up) * j] += taps_[i] * st.taps[j];
      }
      taps_.swap(h);
      latency += st.half * up;
      up *= st.ratio;
    }
    latency_in_ = static_cast<size_t>(latency);
    half_width_s_ = static_cast<double>(latency) / fi;
  } else {
    const double fs = 0.5 * fo;
    cutoff_hz_ = 0.5 * (fp + fs);
    beta_ = kaiserBeta(a);
    half_width_s_ = kaiserHalfWidth(a, fs - fp);
    latency_in_ = static_cast<size_t>(std::ceil(half_width_s_ * fi));
    // Tabulate the kernel on [0, T] with 512 points per output period.
    table_step_s_ = 1.0 / (512.0 * fo);
    const size_t n = static_cast<size_t>(std::ceil(half_width_s_ / table_step_s_)) + 2;
    table_.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const double tau = static_cast<double>(i) * table_step_s_;
      table_[i] = 2.0 * cutoff_hz_ * sinc(2.0 * cutoff_hz_ * tau) * kaiser(tau / half_width_s_, beta_);
    }
  }
  reset(t0_s);
}

std::vector<int> Decimator::stageRatios() const {
  std::vector<int> r;
  for (const FirStage& st : stages_) r.push_back(st.ratio);
  return r;
}

void Decimator::reset(double t0_s) {
  t0_ = t0_s;
  buf_.clear();
  buf_first_ = 0;
  first_.assign(channels_, 0.0);
  last_.assign(channels_, 0.0);
  for (FirStage& st : stages_) {
    st.buf.clear();
    st.buf_first = 0;
    st.n_in = st.n_out = 0;
    st.first.assign(channels_, 0.0);
    st.last.assign(channels_, 0.0);
  }
  n_in_ = 0;
  n_out_ = 0;
  flushed_ = false;
}

double Decimator::kernel(double tau_s) const {
  const double x = std::abs(tau_s) / table_step_s_;
  const size_t i = static_cast<size_t>(x);
  if (i + 1 >= table_.size()) return 0.0;
  const double f = x - static_cast<double>(i);
  return table_[i] + f * (table_[i + 1] - table_[i]);
}

double Decimator::inputAt(int64_t n, size_t c) const {
  if (n < 0) return first_[c];
  if (n >= static_cast<int64_t>(n_in_)) return last_[c];
  return buf_[static_cast<size_t>(n - buf_first_) * channels_ + c];
}

void Decimator::runStage(FirStage& st, const double* x, size_t frames, bool flushing, std::vector<double>& out) const {
  const size_t nc = channels_;
  if (frames > 0) {
    if (st.n_in == 0) st.first.assign(x, x + nc);
    st.buf.insert(st.buf.end(), x, x + frames * nc);
    st.n_in += frames;
    st.last.assign(x + (frames - 1) * nc, x + frames * nc);
  }
  if (st.n_in == 0) return;
  const int64_t last_in = static_cast<int64_t>(st.n_in) - 1;
  const int64_t d = st.half;
  const size_t ntaps = st.taps.size();
  auto at = [&](int64_t n, size_t c) {
    if (n < 0) return st.first[c];
    if (n > last_in) return st.last[c];
    return st.buf[static_cast<size_t>(n - st.buf_first) * nc + c];
  };
  for (;;) {
    const int64_t centre = static_cast<int64_t>(st.n_out) * st.ratio;
    if (flushing ? centre > last_in : centre + d > last_in) break;
    const int64_t n0 = centre - d;
    const size_t base = out.size();
    out.resize(base + nc, 0.0);
    double* o = out.data() + base;
    if (n0 >= st.buf_first && n0 + static_cast<int64_t>(ntaps) - 1 <= last_in) {
      const double* xs = st.buf.data() + static_cast<size_t>(n0 - st.buf_first) * nc;
      if (nc == 1) {
        double s = 0.0;
        for (size_t j = 0; j < ntaps; ++j) s += st.taps[j] * xs[j];
        o[0] = s;
      } else {
        for (size_t j = 0; j < ntaps; ++j) {
          const double h = st.taps[j];
          const double* xj = xs + j * nc;
          for (size_t c = 0; c < nc; ++c) o[c] += h * xj[c];
        }
      }
    } else {
      for (size_t j = 0; j < ntaps; ++j) {
        for (size_t c = 0; c < nc; ++c) o[c] += st.taps[j] * at(n0 + static_cast<int64_t>(j), c);
      }
    }
    ++st.n_out;
  }
  // Drop frames no longer needed (amortised: only when at least half the buffer is stale).
  const int64_t keep_from = std::min<int64_t>(static_cast<int64_t>(st.n_out) * st.ratio - d, last_in);
  const int64_t drop = keep_from - st.buf_first;
  if (drop > 0 && 2 * drop >= static_cast<int64_t>(st.buf.size() / nc)) {
    st.buf.erase(st.buf.begin(), st.buf.begin() + drop * static_cast<int64_t>(nc));
    st.buf_first += drop;
  }
}

size_t Decimator::push(const double* interleaved, size_t frames, std::vector<double>& out) {
  if (flushed_) throw std::logic_error("Decimator::push after flush()");
  if (frames == 0) return 0;
  n_in_ += frames;
  const size_t before = out.size();
  if (!stages_.empty()) {
    if (stages_.size() == 1) {
      runStage(stages_[0], interleaved, frames, false, out);
    } else {
      stage_tmp_.clear();
      runStage(stages_[0], interleaved, frames, false, stage_tmp_);
      runStage(stages_[1], stage_tmp_.data(), stage_tmp_.size() / channels_, false, out);
    }
  } else {
    if (n_in_ == frames) first_.assign(interleaved, interleaved + channels_);
    buf_.insert(buf_.end(), interleaved, interleaved + frames * channels_);
    last_.assign(interleaved + (frames - 1) * channels_, interleaved + frames * channels_);
    emitReady(out, false);
  }
  const size_t added = (out.size() - before) / channels_;
  n_out_ += added;
  return added;
}

size_t Decimator::flush(std::vector<double>& out) {
  if (flushed_) return 0;
  flushed_ = true;
  if (n_in_ == 0) return 0;
  const size_t before = out.size();
  if (!stages_.empty()) {
    if (stages_.size() == 1) {
      runStage(stages_[0], nullptr, 0, true, out);
    } else {
      stage_tmp_.clear();
      runStage(stages_[0], nullptr, 0, true, stage_tmp_);
      runStage(stages_[1], stage_tmp_.data(), stage_tmp_.size() / channels_, true, out);
    }
  } else {
    emitReady(out, true);
  }
  const size_t added = (out.size() - before) / channels_;
  n_out_ += added;
  return added;
}

// Non-integer ratio: kernel evaluated at the fractional offsets of each output time.
void Decimator::emitReady(std::vector<double>& out, bool flushing) {
  const int64_t last_in = static_cast<int64_t>(n_in_) - 1;
  const double fi = spec_.input_rate_hz;
  const double r = fi / spec_.output_rate_hz;
  const size_t nc = channels_;
  const double hw = half_width_s_ * fi;  // half width in input samples
  uint64_t k = n_out_;
  for (;;) {
    const double p = static_cast<double>(k) * r;
    const int64_t lo = static_cast<int64_t>(std::ceil(p - hw));
    const int64_t hi = static_cast<int64_t>(std::floor(p + hw));
    if (flushing ? p > static_cast<double>(last_in) + 1e-9 : hi > last_in) break;
    const size_t base = out.size();
    out.resize(base + nc, 0.0);
    double wsum = 0.0;
    double* o = out.data() + base;
    const bool inside = lo >= buf_first_ && hi <= last_in;
    for (int64_t n = lo; n <= hi; ++n) {
      const double w = kernel((static_cast<double>(n) - p) / fi);
      wsum += w;
      if (inside) {
        const double* xn = buf_.data() + static_cast<size_t>(n - buf_first_) * nc;
        for (size_t c = 0; c < nc; ++c) o[c] += w * xn[c];
      } else {
        for (size_t c = 0; c < nc; ++c) o[c] += w * inputAt(n, c);
      }
    }
    for (size_t c = 0; c < nc; ++c) out[base + c] /= wsum;
    ++k;
  }
  const int64_t keep_from =
      std::min<int64_t>(static_cast<int64_t>(std::ceil(static_cast<double>(k) * r - hw)) - 1, last_in);
  const int64_t drop = keep_from - buf_first_;
  if (drop > 0 && 2 * drop >= static_cast<int64_t>(buf_.size() / nc)) {
    buf_.erase(buf_.begin(), buf_.begin() + drop * static_cast<int64_t>(nc));
    buf_first_ += drop;
  }
}

double Decimator::responseMagnitude(double f_hz) const {
  const double fi = spec_.input_rate_hz;
  if (ratio_ > 0) {
    const int64_t d = static_cast<int64_t>(latency_in_);
    double s = 0.0;
    for (int64_t j = -d; j <= d; ++j) {
      s += taps_[static_cast<size_t>(j + d)] * std::cos(2.0 * kPi * f_hz * static_cast<double>(j) / fi);
    }
    return std::abs(s);
  }
  // Continuous kernel (the response for a fractional output phase differs only by sampling effects).
  double s = 0.0;
  double w = 0.0;
  const int64_t m = static_cast<int64_t>(std::ceil(half_width_s_ * fi));
  for (int64_t j = -m; j <= m; ++j) {
    const double k = kernel(static_cast<double>(j) / fi);
    s += k * std::cos(2.0 * kPi * f_hz * static_cast<double>(j) / fi);
    w += k;
  }
  return std::abs(s / w);
}

std::vector<double> Decimator::decimate(const std::vector<double>& x, const DecimatorSpec& spec) {
  Decimator d(spec, 1);
  std::vector<double> out;
  out.reserve(static_cast<size_t>(static_cast<double>(x.size()) * spec.output_rate_hz / spec.input_rate_hz) + 2);
  d.push(x, out);
  d.flush(out);
  return out;
}

// ---------------------------------------------------------- StreamInterpolator

StreamInterpolator::StreamInterpolator(double rate_hz, size_t channels, double t0_s, InterpolationKind kind,
                                       int sinc_half_width)
    : rate_(rate_hz), channels_(channels), t0_(t0_s), kind_(kind) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) throw std::invalid_argument("StreamInterpolator: rate must be > 0");
  if (channels == 0) throw std::invalid_argument("StreamInterpolator: at least one channel");
  if (kind == InterpolationKind::Cubic) {
    reach_ = 2;
  } else {
    if (sinc_half_width < 2 || sinc_half_width > 256) {
      throw std::invalid_argument("StreamInterpolator: sinc_half_width must be in [2, 256]");
    }
    reach_ = sinc_half_width;
    beta_ = 6.0;
  }
  first_.assign(channels_, 0.0);
}

void StreamInterpolator::push(const double* interleaved, size_t frames) {
  if (finished_) throw std::logic_error("StreamInterpolator::push after finish()");
  if (frames == 0) return;
  if (count_ == 0) first_.assign(interleaved, interleaved + channels_);
  buf_.insert(buf_.end(), interleaved, interleaved + frames * channels_);
  count_ += static_cast<int64_t>(frames);
}

double StreamInterpolator::availableUntil() const {
  if (count_ == 0) return -std::numeric_limits<double>::infinity();
  if (finished_) return std::numeric_limits<double>::infinity();
  return t0_ + static_cast<double>(count_ - 1 - reach_) / rate_;
}

double StreamInterpolator::sampleAt(int64_t n, size_t c) const {
  if (n < 0) return first_[c];
  if (n >= count_) return buf_[buf_.size() - channels_ + c];  // finished: hold the last value
  if (n < buf_first_) throw std::out_of_range("StreamInterpolator: sample already discarded");
  return buf_[static_cast<size_t>(n - buf_first_) * channels_ + c];
}

double StreamInterpolator::weight(double x) const {
  const double ax = std::abs(x);
  if (kind_ == InterpolationKind::Cubic) {
    constexpr double a = -0.5;
    if (ax <= 1.0) return ((a + 2.0) * ax - (a + 3.0)) * ax * ax + 1.0;
    if (ax < 2.0) return ((a * ax - 5.0 * a) * ax + 8.0 * a) * ax - 4.0 * a;
    return 0.0;
  }
  return sinc(x) * kaiser(x / static_cast<double>(reach_), beta_);
}

void StreamInterpolator::evaluate(double t_s, double* out) const {
  if (count_ == 0) throw std::out_of_range("StreamInterpolator: no sample yet");
  if (!(t_s <= availableUntil())) {
    throw std::out_of_range("StreamInterpolator: time " + std::to_string(t_s) + " s not available yet (until " +
                            std::to_string(availableUntil()) + " s)");
  }
  const double p = (t_s - t0_) * rate_;
  const double fl = std::floor(p);
  const int64_t i0 = static_cast<int64_t>(fl);
  const double frac = p - fl;
  std::fill(out, out + channels_, 0.0);
  if (frac == 0.0 && kind_ == InterpolationKind::Cubic) {
    for (size_t c = 0; c < channels_; ++c) out[c] = sampleAt(i0, c);
    return;
  }
  double wsum = 0.0;
  for (int64_t n = i0 - reach_ + 1; n <= i0 + reach_; ++n) {
    const double w = weight(static_cast<double>(n - i0) - frac);
    wsum += w;
    for (size_t c = 0; c < channels_; ++c) out[c] += w * sampleAt(n, c);
  }
  for (size_t c = 0; c < channels_; ++c) out[c] /= wsum;
}

std::vector<double> StreamInterpolator::evaluate(double t_s) const {
  std::vector<double> v(channels_);
  evaluate(t_s, v.data());
  return v;
}

void StreamInterpolator::discardBefore(double t_s) {
  const int64_t keep = static_cast<int64_t>(std::floor((t_s - t0_) * rate_)) - reach_;
  const int64_t limit = count_ - 1;  // always keep the last sample
  const int64_t drop = std::min(keep, limit) - buf_first_;
  if (drop > 0) {
    buf_.erase(buf_.begin(), buf_.begin() + drop * static_cast<int64_t>(channels_));
    buf_first_ += drop;
  }
}

}  // namespace railvib::signal
