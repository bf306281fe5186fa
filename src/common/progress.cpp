#include "railvib/common/progress.hpp"

#include <algorithm>
#include <cmath>

namespace railvib {

ProgressReporter::ProgressReporter(std::string name, double total_s, double period_s, std::FILE* out)
    : name_(std::move(name)),
      total_s_(total_s),
      period_s_(period_s),
      out_(out),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

double ProgressReporter::wallSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double ProgressReporter::realTimeFactor(double t_s) const {
  const double wall = wallSeconds();
  const double t0 = t_start_ < 0.0 ? 0.0 : t_start_;
  return wall > 0.0 ? (t_s - t0) / wall : 0.0;
}

std::string ProgressReporter::line(double t_s) const {
  const double fraction = total_s_ > 0.0 ? std::clamp(t_s / total_s_, 0.0, 1.0) : 1.0;
  const double rtf = realTimeFactor(t_s);
  char eta[32] = "--:--";
  if (rtf > 0.0 && fraction < 1.0) {
    const double remaining = (total_s_ - t_s) / rtf;
    const long s = static_cast<long>(std::lround(remaining));
    std::snprintf(eta, sizeof(eta), "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  } else if (fraction >= 1.0) {
    std::snprintf(eta, sizeof(eta), "done");
  }
  char buf[256];
  std::snprintf(buf, sizeof(buf), "[%s] %5.1f %%  t = %.3f / %.3f s  real-time factor %.3g  ETA %s", name_.c_str(),
                100.0 * fraction, t_s, total_s_, rtf, eta);
  return buf;
}

void ProgressReporter::update(double t_s, bool force) {
  if (t_start_ < 0.0) t_start_ = t_s;
  const auto now = std::chrono::steady_clock::now();
  if (!force && std::chrono::duration<double>(now - last_print_).count() < period_s_) return;
  last_print_ = now;
  if (out_) {
    std::fprintf(out_, "%s\n", line(t_s).c_str());
    std::fflush(out_);
  }
}

void ProgressReporter::finish(double t_s) {
  if (out_) {
    std::fprintf(out_, "[%s] finished: %.3f s simulated in %.2f s wall (real-time factor %.3g)\n", name_.c_str(), t_s,
                 wallSeconds(), realTimeFactor(t_s));
    std::fflush(out_);
  }
}

}  // namespace railvib
