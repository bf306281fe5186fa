// railvib/signal: band-limited differentiation (velocity -> acceleration for
// virtual accelerometers) and integration helpers.
//
// Differentiator: linear-phase FIR, the ideal band-limited differentiator
// h[j] = (wc cos(wc j) / (pi j) - sin(wc j) / (pi j^2)) * fs (wc = 2 pi * 0.47
// rad/sample) under a Kaiser window (beta 10, half width M samples). Same time
// convention as the Decimator: output n stands for t0 + n / rate exactly (no
// group delay) and is emitted once input n + M has arrived (latency M
// samples); flush() pads with the last value. Magnitude error < 3e-5
// relative (M = 24) from DC to 0.4 of the rate, i.e. the decimator's pass band.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace railvib::signal {

class Differentiator {
 public:
  Differentiator(double rate_hz, size_t channels, double t0_s = 0.0, int half_width = 24);

  size_t channels() const { return channels_; }
  size_t latencySamples() const { return static_cast<size_t>(m_); }
  double outputTime(uint64_t n) const { return t0_ + static_cast<double>(n) / rate_; }
  uint64_t outputCount() const { return n_out_; }
  /// Push interleaved frames; completed derivative frames are appended to out. Returns frames appended.
  size_t push(const double* interleaved, size_t frames, std::vector<double>& out);
  size_t push(const std::vector<double>& interleaved, std::vector<double>& out) {
    return push(interleaved.data(), interleaved.size() / channels_, out);
  }
  /// End of stream: emits the remaining outputs (input padded with its last value).
  size_t flush(std::vector<double>& out);
  /// Magnitude of the response relative to the ideal 2 pi f (design check).
  double relativeResponse(double f_hz) const;

 private:
  double at(int64_t n, size_t c) const;
  /// Append output sample n_out_ of every channel and advance n_out_.
  void emitNext(std::vector<double>& out);
  double rate_;
  size_t channels_;
  double t0_;
  int m_;
  std::vector<double> h_;  // h_[j + m], j = -m..m
  std::vector<double> buf_;
  int64_t buf_first_ = 0;
  uint64_t n_in_ = 0, n_out_ = 0;
  std::vector<double> first_, last_;
  bool flushed_ = false;
};

/// Offline derivative of one channel (same FIR, record ends padded with the end values).
std::vector<double> differentiate(const std::vector<double>& x, double fs_hz);
/// Cumulative trapezoidal integral, y[0] = initial.
std::vector<double> integrateTrapezoid(const std::vector<double>& x, double fs_hz, double initial = 0.0);

}  // namespace railvib::signal
