#include "railvib/vehicle/unevenness.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "railvib/common/stream_contract.hpp"
#include "railvib/io/csv.hpp"

namespace railvib::vehicle {

double defectClimbLength(const DefectParams& d, double R) {
  return std::sqrt(std::max(0.0, 2.0 * R * d.height_m - d.height_m * d.height_m));
}

double defectEnvelope(double x, const DefectParams& d, double R) {
  if (!d.enabled || d.height_m <= 0.0) return 0.0;
  const double x0 = d.position_m, x1 = d.position_m + d.length_m;
  const double dist = x < x0 ? x0 - x : (x > x1 ? x - x1 : 0.0);
  if (dist >= R) return 0.0;
  return std::max(0.0, d.height_m - R + std::sqrt(R * R - dist * dist));
}

double defectEnvelopeBruteForce(double x, const DefectParams& d, double R, int samples) {
  // r(xi) = h on [x0, x1], 0 elsewhere; scan xi over [x - R, x + R].
  double best = -1e300;
  for (int k = 0; k < samples; ++k) {
    const double xi = x - R + 2.0 * R * k / (samples - 1);
    const double r = (d.enabled && xi >= d.position_m && xi <= d.position_m + d.length_m) ? d.height_m : 0.0;
    const double dx = x - xi;
    best = std::max(best, r + std::sqrt(std::max(0.0, R * R - dx * dx)));
  }
  // the pad corners exactly (the grid may miss them)
  for (double xi : {d.position_m, d.position_m + d.length_m}) {
    const double dx = x - xi;
    if (d.enabled && std::abs(dx) <= R) best = std::max(best, d.height_m + std::sqrt(R * R - dx * dx));
  }
  return best - R;
}

double Unevenness::psd(double W) const {
  const auto& r = params_.random;
  if (r.psd == "fra") {
    const double Wc2 = r.fra_cutoff_rad_m * r.fra_cutoff_rad_m;
    return r.fra_k * r.fra_a_m2_rad_m * Wc2 / (W * W * (W * W + Wc2));
  }
  return r.power_law_a_m3_rad * std::pow(r.power_law_ref_rad_m / W, r.power_law_exponent);
}

Unevenness::Unevenness(const UnevennessParams& params, double x_min, double x_max) : params_(params) {
  const auto& r = params_.random;
  if (r.enabled) {
    // Sum of cosines: z(x) = sum_k sqrt(2 S(W_k) dW) cos(W_k x + phi_k), W_k
    // log-spaced between 2 pi / max_wavelength and 2 pi / min_wavelength,
    // phases uniform from a seeded mt19937_64 (reproducible across runs).
    const double W0 = 2.0 * M_PI / r.max_wavelength_m, W1 = 2.0 * M_PI / r.min_wavelength_m;
    const int n = r.component_count;
    std::mt19937_64 rng(r.seed);
    std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
    std::vector<double> W(n), A(n), phi(n);
    for (int k = 0; k < n; ++k) {
      const double lo = W0 * std::pow(W1 / W0, static_cast<double>(k) / n);
      const double hi = W0 * std::pow(W1 / W0, static_cast<double>(k + 1) / n);
      W[k] = std::sqrt(lo * hi);
      A[k] = std::sqrt(2.0 * psd(W[k]) * (hi - lo));
      phi[k] = phase(rng);
    }
    grid_x0_ = x_min;
    grid_dx_ = r.grid_spacing_m;
    const size_t count = static_cast<size_t>(std::ceil((x_max - x_min) / grid_dx_)) + 2;
    random_grid_.assign(count, 0.0);
    for (size_t i = 0; i < count; ++i) {
      const double x = x_min + grid_dx_ * static_cast<double>(i);
      double z = 0.0;
      for (int k = 0; k < n; ++k) z += A[k] * std::cos(W[k] * x + phi[k]);
      random_grid_[i] = z;
    }
  }
  if (params_.measured.enabled) {
    const io::CsvTable table = io::readCsv(params_.measured.file);
    const size_t cx = table.column("x_m"), cz = table.column("z_m");
    for (size_t i = 0; i < table.rows.size(); ++i) {
      const auto& row = table.rows[i];
      const std::string line = params_.measured.file + ":" + std::to_string(table.line_of_row[i]);
      if (!measured_x_.empty() && !(row[cx] > measured_x_.back())) {
        throw std::runtime_error("measured profile " + line + ": x_m = " + formatValue(row[cx]) +
                                 ": must be greater than the previous row's " + formatValue(measured_x_.back()));
      }
      const double z = params_.measured.scale * row[cz];
      if (!(std::abs(z) <= params_.measured.max_abs_m)) {
        throw std::runtime_error("measured profile " + line + ": z_m = " + formatValue(row[cz]) + " (x scale " +
                                 formatValue(params_.measured.scale) + "): beyond the " +
                                 formatValue(params_.measured.max_abs_m) +
                                 " m a rail unevenness may be "
                                 "(limits.unevenness_m)");
      }
      measured_x_.push_back(row[cx]);
      measured_z_.push_back(z);
    }
    if (measured_x_.size() < 2) {
      throw std::runtime_error("measured profile " + params_.measured.file + ": needs at least two rows");
    }
  }
}

double Unevenness::defectHeight(double x, double R) const { return defectEnvelope(x, params_.defect, R); }

double Unevenness::randomHeight(double x) const {
  if (random_grid_.empty()) return 0.0;
  const double s = (x - grid_x0_) / grid_dx_;
  if (s <= 0.0) return random_grid_.front();
  const size_t i = static_cast<size_t>(s);
  if (i + 1 >= random_grid_.size()) return random_grid_.back();
  const double f = s - static_cast<double>(i);
  return (1.0 - f) * random_grid_[i] + f * random_grid_[i + 1];
}

double Unevenness::measuredHeight(double x) const {
  if (measured_x_.empty() || x < measured_x_.front() || x > measured_x_.back()) return 0.0;
  const auto it = std::upper_bound(measured_x_.begin(), measured_x_.end(), x);
  const size_t j = std::min<size_t>(static_cast<size_t>(it - measured_x_.begin()), measured_x_.size() - 1);
  const size_t i = j - 1;
  const double f = (x - measured_x_[i]) / (measured_x_[j] - measured_x_[i]);
  return (1.0 - f) * measured_z_[i] + f * measured_z_[j];
}

double Unevenness::height(double x, double R) const { return defectHeight(x, R) + randomHeight(x) + measuredHeight(x); }

}  // namespace railvib::vehicle
