// railvib/signal: band-limited differentiator and integration helpers.
#include "railvib/signal/differentiator.hpp"

#include <cmath>
#include <stdexcept>

#include "railvib/common/constants.hpp"
#include "railvib/signal/filter_design.hpp"

namespace railvib::signal {

Differentiator::Differentiator(double rate_hz, size_t channels, double t0_s, int half_width)
    : rate_(rate_hz), channels_(channels), t0_(t0_s), m_(half_width) {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("Differentiator: rate must be > 0");
  if (channels == 0) throw std::invalid_argument("Differentiator: at least one channel");
  if (half_width < 4 || half_width > 512) throw std::invalid_argument("Differentiator: half width in [4, 512]");
  const double wc = 2.0 * kPi * 0.47;
  const double beta = 10.0;
  h_.assign(2 * static_cast<size_t>(m_) + 1, 0.0);
  for (int j = 1; j <= m_; ++j) {
    const double dj = static_cast<double>(j);
    const double ideal = (wc * std::cos(wc * dj) / (kPi * dj) - std::sin(wc * dj) / (kPi * dj * dj)) * rate_hz;
    const double u = dj / (static_cast<double>(m_) + 1.0);
    const double w = besselI0(beta * std::sqrt(1.0 - u * u)) / besselI0(beta);
    h_[static_cast<size_t>(m_ + j)] = ideal * w;
    h_[static_cast<size_t>(m_ - j)] = -ideal * w;
  }
  first_.assign(channels, 0.0);
  last_.assign(channels, 0.0);
}

double Differentiator::at(int64_t n, size_t c) const {
  if (n < 0) return first_[c];
  if (n >= static_cast<int64_t>(n_in_)) return last_[c];
  return buf_[static_cast<size_t>(n - buf_first_) * channels_ + c];
}

size_t Differentiator::push(const double* x, size_t frames, std::vector<double>& out) {
  if (flushed_) throw std::logic_error("Differentiator::push after flush()");
  if (frames == 0) return 0;
  if (n_in_ == 0) first_.assign(x, x + channels_);
  buf_.insert(buf_.end(), x, x + frames * channels_);
  n_in_ += frames;
  last_.assign(x + (frames - 1) * channels_, x + frames * channels_);
  const size_t before = out.size();
  // y[n] = sum_j h[j] x[n - j], j = -m..m: needs x up to n + m.
  while (static_cast<int64_t>(n_out_) + m_ <= static_cast<int64_t>(n_in_) - 1) {
    emitNext(out);
  }
  const int64_t keep = static_cast<int64_t>(n_out_) - m_;
  const int64_t drop = keep - buf_first_;
  if (drop > 0 && 2 * drop >= static_cast<int64_t>(buf_.size() / channels_)) {
    buf_.erase(buf_.begin(), buf_.begin() + drop * static_cast<int64_t>(channels_));
    buf_first_ += drop;
  }
  return (out.size() - before) / channels_;
}

size_t Differentiator::flush(std::vector<double>& out) {
  if (flushed_) return 0;
  const size_t before = out.size();
  while (n_out_ < n_in_) {
    emitNext(out);
  }
  flushed_ = true;
  return (out.size() - before) / channels_;
}

void Differentiator::emitNext(std::vector<double>& out) {
  const int64_t n = static_cast<int64_t>(n_out_);
  for (size_t c = 0; c < channels_; ++c) {
    double s = 0.0;
    for (int j = -m_; j <= m_; ++j) s += h_[static_cast<size_t>(j + m_)] * at(n - j, c);
    out.push_back(s);
  }
  ++n_out_;
}

double Differentiator::relativeResponse(double f_hz) const {
  // H(f) = sum_j h[j] e^{-i w j} = -2 i sum_{j>0} h[j] sin(w j) (h odd); ideal i 2 pi f.
  const double w = 2.0 * kPi * f_hz / rate_;
  double s = 0.0;
  for (int j = 1; j <= m_; ++j) s += h_[static_cast<size_t>(m_ + j)] * std::sin(w * j);
  return -2.0 * s / (2.0 * kPi * f_hz);
}

std::vector<double> differentiate(const std::vector<double>& x, double fs_hz) {
  Differentiator d(fs_hz, 1);
  std::vector<double> out;
  out.reserve(x.size());
  d.push(x, out);
  d.flush(out);
  return out;
}

std::vector<double> integrateTrapezoid(const std::vector<double>& x, double fs_hz, double initial) {
  std::vector<double> y(x.size());
  if (x.empty()) return y;
  y[0] = initial;
  const double h = 0.5 / fs_hz;
  for (size_t i = 1; i < x.size(); ++i) y[i] = y[i - 1] + h * (x[i - 1] + x[i]);
  return y;
}

}  // namespace railvib::signal
