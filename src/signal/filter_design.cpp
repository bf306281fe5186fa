// railvib/signal: IIR filter design by bilinear transform with pre-warping.
#include "railvib/signal/filter_design.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "railvib/common/constants.hpp"

namespace railvib::signal {

namespace {
using cd = std::complex<double>;

void checkRate(double f_hz, double fs_hz, const char* what) {
  if (!(fs_hz > 0.0) || !(f_hz > 0.0) || !(f_hz < 0.5 * fs_hz)) {
    throw std::invalid_argument(std::string(what) + ": frequency " + std::to_string(f_hz) +
                                " Hz must lie in (0, fs/2) with fs = " + std::to_string(fs_hz) + " Hz");
  }
}

// Bilinear map of an analog biquad (B0 s^2 + B1 s + B2) / (A0 s^2 + A1 s + A2).
Biquad bilinear2(double B0, double B1, double B2, double A0, double A1, double A2, double k) {
  const double k2 = k * k;
  const double a0 = A0 * k2 + A1 * k + A2;
  Biquad q;
  q.b0 = (B0 * k2 + B1 * k + B2) / a0;
  q.b1 = 2.0 * (B2 - B0 * k2) / a0;
  q.b2 = (B0 * k2 - B1 * k + B2) / a0;
  q.a1 = 2.0 * (A2 - A0 * k2) / a0;
  q.a2 = (A0 * k2 - A1 * k + A2) / a0;
  return q;
}

// Bilinear map of an analog first-order section (B1 s + B0) / (A1 s + A0).
Biquad bilinear1(double B1, double B0, double A1, double A0, double k) {
  const double a0 = A1 * k + A0;
  Biquad q;
  q.b0 = (B1 * k + B0) / a0;
  q.b1 = (B0 - B1 * k) / a0;
  q.a1 = (A0 - A1 * k) / a0;
  return q;
}

BiquadCascade butterworth(int order, double fc_hz, double fs_hz, double f_match_hz, bool highpass) {
  if (order < 1 || order > 16) throw std::invalid_argument("Butterworth order must be in [1, 16]");
  checkRate(fc_hz, fs_hz, highpass ? "butterworthHighpass" : "butterworthLowpass");
  const double fm = f_match_hz > 0.0 ? f_match_hz : fc_hz;
  checkRate(fm, fs_hz, "Butterworth matching frequency");
  const double k = bilinearConstant(fm, fs_hz);
  const double wc = 2.0 * kPi * fc_hz;
  std::vector<Biquad> sections;
  for (int i = 1; i <= order / 2; ++i) {
    const double c = -2.0 * std::cos((2.0 * i + order - 1.0) * kPi / (2.0 * order));
    if (highpass) {
      sections.push_back(bilinear2(1.0, 0.0, 0.0, 1.0, c * wc, wc * wc, k));
    } else {
      sections.push_back(bilinear2(0.0, 0.0, wc * wc, 1.0, c * wc, wc * wc, k));
    }
  }
  if (order % 2 == 1) {
    sections.push_back(highpass ? bilinear1(1.0, 0.0, 1.0, wc, k) : bilinear1(0.0, wc, 1.0, wc, k));
  }
  return BiquadCascade(std::move(sections));
}
}  // namespace

double besselI0(double x) {
  double sum = 1.0;
  double term = 1.0;
  const double q = 0.25 * x * x;
  for (int k = 1; k < 500; ++k) {
    term *= q / (static_cast<double>(k) * static_cast<double>(k));
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return sum;
}

double kaiserBeta(double a) {
  if (a > 50.0) return 0.1102 * (a - 8.7);
  if (a >= 21.0) return 0.5842 * std::pow(a - 21.0, 0.4) + 0.07886 * (a - 21.0);
  return 0.0;
}

std::complex<double> Biquad::response(double f_hz, double fs_hz) const {
  const cd z1 = std::polar(1.0, -2.0 * kPi * f_hz / fs_hz);
  const cd z2 = z1 * z1;
  return (b0 + b1 * z1 + b2 * z2) / (1.0 + a1 * z1 + a2 * z2);
}

BiquadCascade::BiquadCascade(std::vector<Biquad> sections)
    : sections_(std::move(sections)), state_(2 * sections_.size(), 0.0) {}

std::complex<double> BiquadCascade::response(double f_hz, double fs_hz) const {
  cd h = 1.0;
  for (const Biquad& s : sections_) h *= s.response(f_hz, fs_hz);
  return h;
}

void BiquadCascade::append(const BiquadCascade& other) {
  sections_.insert(sections_.end(), other.sections_.begin(), other.sections_.end());
  state_.assign(2 * sections_.size(), 0.0);
}

double bilinearConstant(double f_match_hz, double fs_hz) {
  checkRate(f_match_hz, fs_hz, "bilinearConstant");
  return 2.0 * kPi * f_match_hz / std::tan(kPi * f_match_hz / fs_hz);
}

BiquadCascade butterworthLowpass(int order, double fc_hz, double fs_hz, double f_match_hz) {
  return butterworth(order, fc_hz, fs_hz, f_match_hz, false);
}

BiquadCascade butterworthHighpass(int order, double fc_hz, double fs_hz, double f_match_hz) {
  return butterworth(order, fc_hz, fs_hz, f_match_hz, true);
}

BiquadCascade firstOrderHighpass(double fc_hz, double fs_hz) { return butterworth(1, fc_hz, fs_hz, 0.0, true); }

BiquadCascade butterworthBandpass(int n, double f1_hz, double f2_hz, double fs_hz) {
  if (n < 1 || n > 8) throw std::invalid_argument("butterworthBandpass: prototype order must be in [1, 8]");
  checkRate(f1_hz, fs_hz, "butterworthBandpass");
  checkRate(f2_hz, fs_hz, "butterworthBandpass");
  if (!(f2_hz > f1_hz)) throw std::invalid_argument("butterworthBandpass: f2 must exceed f1");
  const double k = 2.0 * fs_hz;
  const double w1 = k * std::tan(kPi * f1_hz / fs_hz);
  const double w2 = k * std::tan(kPi * f2_hz / fs_hz);
  const double w0sq = w1 * w2;
  const double bw = w2 - w1;
  std::vector<cd> upper;  // digital poles with Im > 0
  std::vector<double> real_poles;
  for (int i = 0; i < n; ++i) {
    const cd p = std::polar(1.0, kPi * (2.0 * i + n + 1.0) / (2.0 * n));
    const cd root = std::sqrt(p * p * bw * bw - 4.0 * w0sq);
    for (const cd s : {0.5 * (p * bw + root), 0.5 * (p * bw - root)}) {
      const cd z = (k + s) / (k - s);
      if (z.imag() > 1e-14) {
        upper.push_back(z);
      } else if (std::abs(z.imag()) <= 1e-14) {
        real_poles.push_back(z.real());
      }
    }
  }
  std::vector<Biquad> sections;
  for (const cd z : upper) {
    Biquad q;
    q.b0 = 1.0;
    q.b1 = 0.0;
    q.b2 = -1.0;
    q.a1 = -2.0 * z.real();
    q.a2 = std::norm(z);
    sections.push_back(q);
  }
  std::sort(real_poles.begin(), real_poles.end());
  for (size_t i = 0; i + 1 < real_poles.size(); i += 2) {
    Biquad q;
    q.b0 = 1.0;
    q.b2 = -1.0;
    q.a1 = -(real_poles[i] + real_poles[i + 1]);
    q.a2 = real_poles[i] * real_poles[i + 1];
    sections.push_back(q);
  }
  BiquadCascade cascade(sections);
  const double f0 = fs_hz / kPi * std::atan(std::sqrt(w0sq) / k);
  const double g = std::abs(cascade.response(f0, fs_hz));
  const double gs = std::pow(1.0 / g, 1.0 / static_cast<double>(sections.size()));
  for (Biquad& q : sections) {
    q.b0 *= gs;
    q.b1 *= gs;
    q.b2 *= gs;
  }
  return BiquadCascade(std::move(sections));
}

}  // namespace railvib::signal
