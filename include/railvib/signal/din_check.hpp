// railvib/signal: runnable verification of the KB evaluation against the
// DIN 45669-1 / DIN 4150-2 test values (DIN 45669-1 test table, continuous sine of
// amplitude 1 mm/s): KB_F is the steady mean of KB_F(t), KB_Fmax the maximum
// of its ripple (the running rms of a sine oscillates at twice its frequency).
#pragma once

#include <vector>

#include "railvib/signal/vibration.hpp"

namespace railvib::signal {

struct DinCheckRow {
  double f_hz = 0.0;
  double expected_kb_f = 0.0;
  double expected_kb_fmax = 0.0;
  double kb_f = 0.0;            ///< mean of KB_F(t) over whole ripple periods after settling
  double kb_f_rms = 0.0;        ///< sqrt(mean KB_F^2) (= weighted rms of the sine)
  double kb_fmax = 0.0;         ///< max of KB_F(t) after settling
  double kb_fmax_analog = 0.0;  ///< analog prediction |H|/sqrt2 * sqrt(1 + 1/sqrt(1 + (2 w tau)^2))
};

/// Run the test sines (5.6, 16, 31.5, 80 Hz) through KbWeighting at fs.
std::vector<DinCheckRow> din45669TestTable(double fs_hz, const KbSpec& spec = {});

}  // namespace railvib::signal
