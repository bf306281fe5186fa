// railvib/common: one concise progress line for long simulations:
// percent, simulated time, real-time factor and ETA, at most once per period.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace railvib {

class ProgressReporter {
 public:
  /// total_s: simulated time of the whole run; period_s: wall time between lines.
  ProgressReporter(std::string name, double total_s, double period_s = 2.0, std::FILE* out = stderr);

  /// Report progress at simulated time t_s (prints if the period has elapsed, or force).
  void update(double t_s, bool force = false);
  /// Final line with the wall time.
  void finish(double t_s);
  /// The line update() would print now (for tests and diagnostics).
  std::string line(double t_s) const;
  double wallSeconds() const;
  /// Simulated seconds per wall second since start.
  double realTimeFactor(double t_s) const;

 private:
  std::string name_;
  double total_s_;
  double period_s_;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  double t_start_ = -1.0;
};

}  // namespace railvib
