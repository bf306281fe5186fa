// railvib/signal: multi-channel streaming anti-alias decimation / resampling
// and stream interpolation, with an exactly known time alignment.
//
// Time convention (every class here):
//   input sample n  (n = 0, 1, ...) stands for time t0 + n / input_rate;
//   output sample k (k = 0, 1, ...) stands for time t0 + k / output_rate,
// exactly. The low-pass is a linear-phase (symmetric, zero-phase when centred)
// Kaiser-windowed sinc, centred on the output time, so there is no group delay
// in the output: the delay shows up as *latency* instead. Output k is emitted by
// push() as soon as the input samples up to time t_k + halfWidthSeconds() have
// arrived, i.e. latencyInputSamples() input samples after the sample at t_k.
//
// Sample layout: C channels interleaved frame by frame, x[frame * C + c].
// Before t0 the input is taken equal to the first sample (no start-up step;
// a two-stage design pads its intermediate stream the same way).
// flush() ends the stream: the input is padded with its last value and every
// output whose time is <= the time of the last input sample is emitted.
//
// Design (see docs/signal.md): pass band flat to passband_fraction *
// output_rate (ripple < 0.01 dB with the defaults), stop band >= 60 dB from
// output_rate / 2 upwards (designed for stopband_db = 70 with margin).
// Integer ratios input_rate / output_rate use exact precomputed taps, in one
// stage or, when cheaper (e.g. 100 kHz -> 2 kHz: 10 x 5, ~5x fewer
// multiplications), two cascaded stages whose equivalent FIR has
// N = 2 * latencyInputSamples() + 1 taps; non-integer ratios use one stage with
// the continuous kernel evaluated from a finely tabulated copy (error < 1e-5).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace railvib::signal {

struct DecimatorSpec {
  double input_rate_hz = 0.0;
  /// Output rate, <= input rate. input/output integer -> exact integer decimator.
  double output_rate_hz = 0.0;
  /// Pass band edge (flat) as a fraction of the output rate, in (0, 0.5).
  double passband_fraction = 0.4;
  /// Stop band attenuation target (dB) at and above output_rate / 2.
  double stopband_db = 70.0;
};

class Decimator {
 public:
  /// Throws std::invalid_argument on a bad spec (rates <= 0, output > input, ...).
  Decimator(const DecimatorSpec& spec, size_t channels, double t0_s = 0.0);

  size_t channels() const { return channels_; }
  double inputRate() const { return spec_.input_rate_hz; }
  double outputRate() const { return spec_.output_rate_hz; }
  /// Integer ratio input/output, or 0 when the ratio is not an integer.
  int integerRatio() const { return ratio_; }
  double t0() const { return t0_; }

  /// Half length of the anti-alias kernel (seconds): latency of the output.
  double halfWidthSeconds() const { return half_width_s_; }
  /// Latency in input samples: output for time t is emitted once the input at
  /// time t + latencyInputSamples() / input_rate has arrived (ceil for non-integer ratios).
  size_t latencyInputSamples() const { return latency_in_; }
  /// Equivalent single-rate FIR taps at the input rate (integer ratio; the
  /// convolution of the stages), centred, sum 1; empty for non-integer ratios.
  const std::vector<double>& taps() const { return taps_; }

  /// Time of output sample k: t0 + k / output_rate.
  double outputTime(uint64_t k) const { return t0_ + static_cast<double>(k) / spec_.output_rate_hz; }
  /// Number of input frames pushed / output frames emitted so far. The next
  /// emitted output frame has index outputCount().
  uint64_t inputCount() const { return n_in_; }
  uint64_t outputCount() const { return n_out_; }

  /// Push `frames` interleaved input frames; completed output frames are
  /// appended (interleaved) to `out`. Returns the number of output frames appended.
  size_t push(const double* interleaved, size_t frames, std::vector<double>& out);
  size_t push(const std::vector<double>& interleaved, std::vector<double>& out) {
    return push(interleaved.data(), interleaved.size() / channels_, out);
  }
  /// End of stream (pad with the last value). After flush() push() throws.
  size_t flush(std::vector<double>& out);
  bool flushed() const { return flushed_; }
  /// Restart an empty stream at t0.
  void reset(double t0_s = 0.0);

  /// Frequency response magnitude of the kernel at f (Hz) (design check).
  double responseMagnitude(double f_hz) const;

  /// Offline convenience, one channel: decimate a whole record (flushes).
  static std::vector<double> decimate(const std::vector<double>& x, const DecimatorSpec& spec);

  /// Number of FIR stages of an integer ratio (1, or 2 when a split is cheaper).
  size_t stageCount() const { return stages_.size(); }
  /// Decimation ratio of each stage (product = integerRatio()).
  std::vector<int> stageRatios() const;

 private:
  struct FirStage {
    int ratio = 1;
    int64_t half = 0;          // taps = 2 half + 1
    std::vector<double> taps;  // centred, sum 1
    std::vector<double> buf;   // retained input frames, interleaved
    int64_t buf_first = 0;     // stage input index of buf[0]
    uint64_t n_in = 0, n_out = 0;
    std::vector<double> first, last;
  };
  void runStage(FirStage& st, const double* x, size_t frames, bool flushing, std::vector<double>& out) const;
  double kernel(double tau_s) const;  // continuous kernel * (1 / input_rate)
  void emitReady(std::vector<double>& out, bool flushing);
  double inputAt(int64_t n, size_t c) const;

  std::vector<FirStage> stages_;   // integer ratios
  std::vector<double> stage_tmp_;  // stage 1 -> stage 2

  DecimatorSpec spec_;
  size_t channels_;
  double t0_;
  int ratio_ = 0;
  double cutoff_hz_ = 0.0;
  double beta_ = 0.0;
  double half_width_s_ = 0.0;
  size_t latency_in_ = 0;
  std::vector<double> taps_;
  std::vector<double> table_;  // kernel tabulated on [0, half_width] (non-integer ratios)
  double table_step_s_ = 0.0;

  std::vector<double> buf_;  // retained input frames, interleaved
  int64_t buf_first_ = 0;    // input index of buf_[0]
  std::vector<double> first_, last_;
  uint64_t n_in_ = 0;
  uint64_t n_out_ = 0;
  bool flushed_ = false;
};

/// How a StreamInterpolator reconstructs between samples.
enum class InterpolationKind {
  Cubic,        ///< Keys cubic convolution (a = -0.5): 4 samples, exact for quadratics.
  WindowedSinc  ///< Kaiser-windowed sinc, band-limited to ~0.45 of the rate, sinc_half_width samples each side.
};

/// Evaluates a uniformly sampled multi-channel stream at arbitrary times
/// (e.g. the soil reading 2 kHz loads at its own time step). The stream should
/// already be band-limited (e.g. output of a Decimator). Sample n stands for
/// t0 + n / rate. Before t0 the first value is held; after finish() the last.
class StreamInterpolator {
 public:
  StreamInterpolator(double rate_hz, size_t channels, double t0_s = 0.0,
                     InterpolationKind kind = InterpolationKind::Cubic, int sinc_half_width = 16);

  size_t channels() const { return channels_; }
  double rate() const { return rate_; }
  /// Samples needed after t to evaluate at t (2 for cubic, sinc_half_width for sinc), in seconds.
  double lookaheadSeconds() const { return static_cast<double>(reach_) / rate_; }

  void push(const double* interleaved, size_t frames);
  void push(const std::vector<double>& interleaved) { push(interleaved.data(), interleaved.size() / channels_); }
  /// End of stream: the last value is held from then on.
  void finish() { finished_ = true; }
  bool finished() const { return finished_; }

  /// Latest time that can be evaluated now (+inf after finish(), -inf if empty).
  double availableUntil() const;
  bool canEvaluate(double t_s) const { return t_s <= availableUntil(); }
  /// Interpolated values of all channels at t (out has channels() entries).
  /// Throws std::out_of_range if t is beyond availableUntil() or before discarded data.
  void evaluate(double t_s, double* out) const;
  std::vector<double> evaluate(double t_s) const;
  /// Free samples no longer needed to evaluate at times >= t_s.
  void discardBefore(double t_s);

 private:
  double sampleAt(int64_t n, size_t c) const;
  double weight(double x) const;  // kernel at offset x samples

  double rate_;
  size_t channels_;
  double t0_;
  InterpolationKind kind_;
  int reach_;  // samples each side
  double beta_ = 0.0;
  std::vector<double> buf_;
  int64_t buf_first_ = 0;
  int64_t count_ = 0;
  std::vector<double> first_;
  bool finished_ = false;
};

}  // namespace railvib::signal
