#include "railvib/soil/footprint_compliance.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "railvib/soil/footprint.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver.hpp"
#include "railvib/soil/ssi_verification.hpp"

namespace railvib::soil {
namespace {

double rms(const std::vector<double>& v, size_t from, size_t to) {
  double s = 0.0;
  for (size_t n = from; n < to; ++n) s += v[n] * v[n];
  return to > from ? std::sqrt(s / static_cast<double>(to - from)) : 0.0;
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("footprint compliance: " + what);
}

}  // namespace

FootprintCompliance::FootprintCompliance(const SoilParams& params, const FootprintComplianceSpec& spec) {
  const auto t0 = std::chrono::steady_clock::now();
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  require(positive(spec.force_n) && positive(spec.pulse_s) && positive(spec.duration_s),
          "force, pulse and duration must be finite and > 0");
  require(spec.duration_s > spec.pulse_s, "the run must be longer than the pulse");
  require(std::isfinite(spec.max_distance_m) && spec.max_distance_m >= 0.0, "max_distance_m must be >= 0");
  const TrackLayout& layout = params.track;
  spacing_m_ = layout.spacing_m;
  f_max_hz_ = params.mesh.f_max_hz;

  Solver solver(buildMesh(params.profile, params.mesh), params.solver);
  const StructuredMesh& mesh = solver.mesh();
  const LoadableRegion region = loadableRegion(solver, params.solver.absorbing);
  // The loaded sleeper: the one of the layout's rule nearest the region's centre along x.
  const double centre = 0.5 * (region.x_min_m + region.x_max_m);
  loaded_x_m_ = layout.offset_m + spacing_m_ * std::round((centre - layout.offset_m) / spacing_m_);
  require(region.holds(loaded_x_m_, layout), "the footprint at x = " + std::to_string(loaded_x_m_) +
                                                 " m does not fit in the loadable region of the soil box");
  size_t reach = 0;
  while (region.holds(loaded_x_m_ - spacing_m_ * static_cast<double>(reach + 1), layout) &&
         region.holds(loaded_x_m_ + spacing_m_ * static_cast<double>(reach + 1), layout) &&
         (spec.max_distance_m == 0.0 || spacing_m_ * static_cast<double>(reach + 1) <= spec.max_distance_m + 1e-9)) {
    ++reach;
  }
  require(reach >= 2, "the soil box holds " + std::to_string(reach) +
                          " footprints on each side of the loaded one: widen soil.mesh along x (2 at least)");
  // Footprints read: k = 0, then -k and +k for k = 1..reach.
  std::vector<ForceChannel> read;
  read.push_back(sleeperFootprint(mesh, loaded_x_m_, layout));
  for (size_t k = 1; k <= reach; ++k) {
    for (double side : {-1.0, 1.0}) {
      read.push_back(sleeperFootprint(mesh, loaded_x_m_ + side * spacing_m_ * static_cast<double>(k), layout));
    }
  }
  solver.addForceChannel(read.front());

  dt_s_ = solver.dt();
  require(spec.pulse_s >= 4.0 * dt_s_, "the pulse must last 4 steps at least");
  steps_ = static_cast<uint64_t>(std::ceil(spec.duration_s / dt_s_));
  elements_ = mesh.elementCount();
  force_n_.assign(steps_ + 1, 0.0);
  std::vector<std::vector<double>> sides(read.size(), std::vector<double>(steps_ + 1, 0.0));
  std::vector<double> value(1);
  auto displacement = [&](size_t node, int c) { return solver.displacement(node, c); };
  for (uint64_t n = 0; n < steps_; ++n) {
    // The force at t_n drives the step to t_{n+1} (central difference): both on one time grid.
    force_n_[n] = spec.force_n * hannPulse(static_cast<double>(n) * dt_s_, spec.pulse_s);
    value[0] = force_n_[n];
    solver.setChannelValues(value);
    solver.step();
    for (size_t r = 0; r < read.size(); ++r) sides[r][n + 1] = footprintMean(read[r], displacement);
  }
  displacement_m_.assign(reach + 1, std::vector<double>(steps_ + 1, 0.0));
  displacement_m_[0] = sides[0];
  side_difference_ = 0.0;
  for (size_t k = 1; k <= reach; ++k) {
    const std::vector<double>& a = sides[2 * k - 1];
    const std::vector<double>& b = sides[2 * k];
    std::vector<double> diff(steps_ + 1);
    for (size_t n = 0; n <= steps_; ++n) {
      displacement_m_[k][n] = 0.5 * (a[n] + b[n]);
      diff[n] = a[n] - b[n];
    }
    const double mean_rms = rms(displacement_m_[k], 0, steps_ + 1);
    if (mean_rms > 0.0) side_difference_ = std::max(side_difference_, rms(diff, 0, steps_ + 1) / mean_rms);
  }
  const std::vector<double>& u0 = displacement_m_[0];
  const double whole = rms(u0, 0, u0.size());
  tail_share_ = whole > 0.0 ? rms(u0, u0.size() - u0.size() / 10, u0.size()) / whole : 0.0;
  seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::complex<double> FootprintCompliance::compliance(size_t k, double frequency_hz) const {
  if (k >= displacement_m_.size()) {
    std::ostringstream s;
    s << "footprint compliance: distance " << k << " sleepers is beyond the " << displacement_m_.size() - 1
      << " the run read";
    throw std::out_of_range(s.str());
  }
  // Direct Fourier sums by recurrence of the phasor (the step is uniform).
  const double w = 2.0 * M_PI * frequency_hz;
  const std::complex<double> rotate = std::polar(1.0, -w * dt_s_);
  std::complex<double> phasor = 1.0, u = 0.0, f = 0.0;
  const std::vector<double>& disp = displacement_m_[k];
  for (size_t n = 0; n < disp.size(); ++n) {
    u += disp[n] * phasor;
    f += force_n_[n] * phasor;
    phasor *= rotate;
    if ((n & 1023) == 1023) phasor /= std::abs(phasor);  // keep |phasor| = 1 over long runs
  }
  return u / f;
}

nlohmann::json FootprintCompliance::summary() const {
  return {{"elements", elements_},
          {"dt_s", dt_s_},
          {"steps", steps_},
          {"loaded_x_m", loaded_x_m_},
          {"spacing_m", spacing_m_},
          {"footprints_each_side", displacement_m_.size() - 1},
          {"max_distance_m", spacing_m_ * static_cast<double>(displacement_m_.size() - 1)},
          {"f_max_hz", f_max_hz_},
          {"tail_share", tail_share_},
          {"side_difference", side_difference_},
          {"seconds", seconds_}};
}

}  // namespace railvib::soil
