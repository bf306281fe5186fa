#include "railvib/vehicle/unevenness.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "railvib/common/config.hpp"
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

namespace {
/// Linear interpolation on a uniform grid starting at x0 with step dx, held constant beyond its ends.
double gridHeight(const std::vector<double>& grid, double x0, double dx, double x) {
  if (grid.empty()) return 0.0;
  const double s = (x - x0) / dx;
  if (s <= 0.0) return grid.front();
  const size_t i = static_cast<size_t>(s);
  if (i + 1 >= grid.size()) return grid.back();
  const double f = s - static_cast<double>(i);
  return (1.0 - f) * grid[i] + f * grid[i + 1];
}
const char* kMeasuredKey = "unevenness.measured_profile.file";
}  // namespace

Unevenness::Unevenness(const UnevennessParams& params, double x_min, double x_max) : params_(params) {
  const auto& r = params_.random;
  const bool full = params_.width == track::TrackWidth::Full;
  if (r.enabled) {
    // Sum of cosines: z(x) = sum_k sqrt(2 S(W_k) dW) cos(W_k x + phi_k), W_k
    // log-spaced between 2 pi / max_wavelength and 2 pi / min_wavelength,
    // phases uniform from a seeded mt19937_64 (reproducible across runs).
    const double W0 = 2.0 * M_PI / r.max_wavelength_m, W1 = 2.0 * M_PI / r.min_wavelength_m;
    const int n = r.component_count;
    std::mt19937_64 rng(r.seed);
    // The right rail's independent phases: a second generator whose seed no left-rail seed (0 ..
    // 2^31 - 1) takes, so that the rails' incoherent parts are independent draws.
    std::mt19937_64 rng_right(r.seed + (1UL << 31));
    std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
    std::vector<double> W(n), A(n), phi(n), psi(n), coherent(n), incoherent(n);
    for (int k = 0; k < n; ++k) {
      const double lo = W0 * std::pow(W1 / W0, static_cast<double>(k) / n);
      const double hi = W0 * std::pow(W1 / W0, static_cast<double>(k + 1) / n);
      W[k] = std::sqrt(lo * hi);
      A[k] = std::sqrt(2.0 * psd(W[k]) * (hi - lo));
      phi[k] = phase(rng);
    }
    if (full) {
      for (int k = 0; k < n; ++k) {
        psi[k] = phase(rng_right);
        coherent[k] = r.coherence * std::exp(-r.coherence_decay_m_rad * W[k]);
        incoherent[k] = std::sqrt(std::max(0.0, 1.0 - coherent[k] * coherent[k]));
      }
    }
    grid_x0_ = x_min;
    grid_dx_ = r.grid_spacing_m;
    const size_t count = static_cast<size_t>(std::ceil((x_max - x_min) / grid_dx_)) + 2;
    random_grid_[0].assign(count, 0.0);
    for (size_t i = 0; i < count; ++i) {
      const double x = x_min + grid_dx_ * static_cast<double>(i);
      double z = 0.0;
      for (int k = 0; k < n; ++k) z += A[k] * std::cos(W[k] * x + phi[k]);
      random_grid_[0][i] = z;
    }
    if (full && r.coherence == 1.0 && r.coherence_decay_m_rad == 0.0) {
      random_grid_[1] = random_grid_[0];  // fully coherent: both rails alike, exactly
    } else if (full) {
      random_grid_[1].assign(count, 0.0);
      for (size_t i = 0; i < count; ++i) {
        const double x = x_min + grid_dx_ * static_cast<double>(i);
        double z = 0.0;
        for (int k = 0; k < n; ++k)
          z += A[k] * (coherent[k] * std::cos(W[k] * x + phi[k]) + incoherent[k] * std::cos(W[k] * x + psi[k]));
        random_grid_[1][i] = z;
      }
    }
  }
  if (params_.measured.enabled) {
    const io::CsvTable table = io::readCsv(params_.measured.file);
    const auto has = [&](const std::string& c) {
      return std::find(table.columns.begin(), table.columns.end(), c) != table.columns.end();
    };
    const std::string& file = params_.measured.file;
    const bool common = has("z_m"), left = has("z_left_m"), right = has("z_right_m");
    // A profile per rail needs both rails; one column for both rails is the half track's form.
    if (common && (left || right)) {
      throw ConfigError(std::string(kMeasuredKey) + " = " + file +
                        ": has z_m and a rail's column (z_left_m / z_right_m): give one profile for both rails (z_m) "
                        "or one per rail, not both");
    }
    if (!common && !full && (left || right)) {
      throw ConfigError(std::string(kMeasuredKey) + " = " + file +
                        ": a profile per rail (z_left_m, z_right_m) needs track.width: full; the half track has one "
                        "rail standing for both (the symmetric special case): give z_m");
    }
    if (!common && full && left != right) {
      throw ConfigError(std::string(kMeasuredKey) + " = " + file + ": has " + (left ? "z_left_m" : "z_right_m") +
                        " but no " + (left ? "z_right_m" : "z_left_m") +
                        " column: a profile per rail needs both rails' columns (or z_m for both alike)");
    }
    const size_t cx = table.column("x_m");
    std::vector<std::pair<size_t, int>> columns;  // column, rail
    if (common || !(left && right)) {
      columns.push_back({table.column("z_m"), 0});
    } else {
      columns.push_back({table.column("z_left_m"), 0});
      columns.push_back({table.column("z_right_m"), 1});
    }
    for (size_t i = 0; i < table.rows.size(); ++i) {
      const auto& row = table.rows[i];
      const std::string line = file + ":" + std::to_string(table.line_of_row[i]);
      if (!measured_x_.empty() && !(row[cx] > measured_x_.back())) {
        throw std::runtime_error("measured profile " + line + ": x_m = " + formatValue(row[cx]) +
                                 ": must be greater than the previous row's " + formatValue(measured_x_.back()));
      }
      for (const auto& [c, rail] : columns) {
        const double z = params_.measured.scale * row[c];
        if (!(std::abs(z) <= params_.measured.max_abs_m)) {
          throw std::runtime_error("measured profile " + line + ": " + table.columns[c] + " = " + formatValue(row[c]) +
                                   " (x scale " + formatValue(params_.measured.scale) + "): beyond the " +
                                   formatValue(params_.measured.max_abs_m) +
                                   " m a rail unevenness may be "
                                   "(limits.unevenness_m)");
        }
        measured_z_[rail].push_back(z);
      }
      measured_x_.push_back(row[cx]);
    }
    if (measured_x_.size() < 2) {
      throw std::runtime_error("measured profile " + file + ": needs at least two rows");
    }
    // Outside the stretch the wheels run on it would be read as no unevenness at all: a profile in
    // another frame or unit of x.
    if (measured_x_.back() < x_min || measured_x_.front() > x_max) {
      throw std::runtime_error("measured profile " + file + ": x_m covers [" + formatValue(measured_x_.front()) + ", " +
                               formatValue(measured_x_.back()) + "] m, outside the track's [" + formatValue(x_min) +
                               ", " + formatValue(x_max) +
                               "] m where the wheels run (x along the track, the defect at 0, in metres)");
    }
    if (full && columns.size() == 1) measured_z_[1] = measured_z_[0];
  }
}

void Unevenness::checkRail(track::Rail rail) const {
  if (rail == track::Rail::Right && params_.width != track::TrackWidth::Full) {
    throw std::invalid_argument("unevenness: the half track (track.width: half) has no right rail");
  }
}

double Unevenness::defectHeight(double x, double R, track::Rail rail) const {
  checkRail(rail);
  const DefectRails on = params_.defect.rails;
  if ((on == DefectRails::Left && rail != track::Rail::Left) ||
      (on == DefectRails::Right && rail != track::Rail::Right))
    return 0.0;
  return defectEnvelope(x, params_.defect, R);
}

double Unevenness::randomHeight(double x, track::Rail rail) const {
  checkRail(rail);
  return gridHeight(random_grid_[static_cast<int>(rail)], grid_x0_, grid_dx_, x);
}

double Unevenness::measuredHeight(double x, track::Rail rail) const {
  checkRail(rail);
  const std::vector<double>& z = measured_z_[static_cast<int>(rail)];
  if (measured_x_.empty() || x < measured_x_.front() || x > measured_x_.back()) return 0.0;
  const auto it = std::upper_bound(measured_x_.begin(), measured_x_.end(), x);
  const size_t j = std::min<size_t>(static_cast<size_t>(it - measured_x_.begin()), measured_x_.size() - 1);
  const size_t i = j - 1;
  const double f = (x - measured_x_[i]) / (measured_x_[j] - measured_x_[i]);
  return (1.0 - f) * z[i] + f * z[j];
}

double Unevenness::height(double x, double R, track::Rail rail) const {
  return defectHeight(x, R, rail) + randomHeight(x, rail) + measuredHeight(x, rail);
}

}  // namespace railvib::vehicle
