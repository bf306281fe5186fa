// railvib/signal: DIN 45669-1 test table computed with KbWeighting.
#include "railvib/signal/din_check.hpp"

#include <algorithm>
#include <cmath>

#include "railvib/common/constants.hpp"

namespace railvib::signal {

std::vector<DinCheckRow> din45669TestTable(double fs_hz, const KbSpec& spec) {
  const double f[] = {5.6, 16.0, 31.5, 80.0};
  const double kbf[] = {0.500, 0.667, 0.693, 0.594};
  const double kbfmax[] = {0.528, 0.680, 0.700, 0.597};
  std::vector<DinCheckRow> rows;
  for (int i = 0; i < 4; ++i) {
    DinCheckRow r;
    r.f_hz = f[i];
    r.expected_kb_f = kbf[i];
    r.expected_kb_fmax = kbfmax[i];
    KbWeighting kb(fs_hz, spec);
    // Settle 6 s (band-limit high pass and tau), then measure over whole periods (>= 2 s).
    const double settle_s = 6.0;
    const double period = 1.0 / f[i];
    const double measure_s = std::ceil(2.0 / period) * period;
    const size_t n_settle = static_cast<size_t>(settle_s * fs_hz);
    const size_t n_total = n_settle + static_cast<size_t>(std::llround(measure_s * fs_hz));
    double sum = 0.0, sum_sq = 0.0, mx = 0.0;
    for (size_t n = 0; n < n_total; ++n) {
      const double t = static_cast<double>(n) / fs_hz;
      const double kbf_t = kb.process(std::sin(2.0 * kPi * f[i] * t));
      if (n >= n_settle) {
        sum += kbf_t;
        sum_sq += kbf_t * kbf_t;
        mx = std::max(mx, kbf_t);
      }
    }
    const double m = static_cast<double>(n_total - n_settle);
    r.kb_f = sum / m;
    r.kb_f_rms = std::sqrt(sum_sq / m);
    r.kb_fmax = mx;
    const double mean = std::abs(KbWeighting::analogResponse(f[i], spec)) / std::sqrt(2.0);
    const double x = 2.0 * 2.0 * kPi * f[i] * spec.tau_s;
    r.kb_fmax_analog = mean * std::sqrt(1.0 + 1.0 / std::sqrt(1.0 + x * x));
    rows.push_back(r);
  }
  return rows;
}

}  // namespace railvib::signal
