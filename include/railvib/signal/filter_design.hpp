// railvib/signal: IIR filter design (bilinear transform with pre-warping) and
// streaming second-order-section cascades.
//
// Every design maps an analog prototype H(s) to H(z) with
//   s = K (1 - z^-1) / (1 + z^-1),  K = 2 pi f_m / tan(pi f_m / fs),
// so the digital response equals the analog one exactly at the matching
// frequency f_m (the corner unless stated) and the frequency axis is only
// warped elsewhere (tan law). Sections run in transposed direct form II.
#pragma once

#include <complex>
#include <cstddef>
#include <vector>

namespace railvib::signal {

/// Modified Bessel function of the first kind, order 0 (series).
double besselI0(double x);
/// Kaiser window shape parameter for a stop band attenuation of `attenuation_db`.
double kaiserBeta(double attenuation_db);

/// One second-order section y = (b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2) x.
struct Biquad {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
  std::complex<double> response(double f_hz, double fs_hz) const;
};

/// A cascade of sections with the state of one channel.
class BiquadCascade {
 public:
  BiquadCascade() = default;
  explicit BiquadCascade(std::vector<Biquad> sections);

  double process(double x) {
    for (size_t i = 0; i < sections_.size(); ++i) {
      const Biquad& s = sections_[i];
      double* z = &state_[2 * i];
      const double y = s.b0 * x + z[0];
      z[0] = s.b1 * x - s.a1 * y + z[1];
      z[1] = s.b2 * x - s.a2 * y;
      x = y;
    }
    return x;
  }
  void process(const double* in, double* out, size_t n) {
    for (size_t i = 0; i < n; ++i) out[i] = process(in[i]);
  }
  void reset() { state_.assign(state_.size(), 0.0); }
  /// Complex frequency response of the whole cascade.
  std::complex<double> response(double f_hz, double fs_hz) const;
  const std::vector<Biquad>& sections() const { return sections_; }
  /// Append another cascade's sections (series connection).
  void append(const BiquadCascade& other);

 private:
  std::vector<Biquad> sections_;
  std::vector<double> state_;
};

/// Bilinear constant K that maps analog f_match exactly onto digital f_match.
double bilinearConstant(double f_match_hz, double fs_hz);

/// Butterworth low pass of even or odd `order`, -3 dB corner fc; analog response matched at f_match (default fc).
BiquadCascade butterworthLowpass(int order, double fc_hz, double fs_hz, double f_match_hz = 0.0);
/// Butterworth high pass; analog response matched at f_match (default fc).
BiquadCascade butterworthHighpass(int order, double fc_hz, double fs_hz, double f_match_hz = 0.0);
/// First-order high pass s / (s + 2 pi fc).
BiquadCascade firstOrderHighpass(double fc_hz, double fs_hz);
/// Butterworth band pass of order 2 * prototype_order between f1 and f2 (both
/// edges pre-warped, -3 dB at f1 and f2), gain 1 at the digital centre.
BiquadCascade butterworthBandpass(int prototype_order, double f1_hz, double f2_hz, double fs_hz);

}  // namespace railvib::signal
