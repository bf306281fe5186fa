#include "railvib/coupling/track_on_soil.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "railvib/track/track_model.hpp"

namespace railvib::coupling {

track::GroundCompliance feSoilGround(const soil::FootprintCompliance& soil, double track_spacing_m, size_t sleepers,
                                     size_t reach_sleepers) {
  if (!(std::abs(soil.spacingM() - track_spacing_m) <= 1e-9 * track_spacing_m)) {
    std::ostringstream s;
    s << "the soil run's footprints are " << soil.spacingM() << " m apart, the track's sleepers " << track_spacing_m
      << " m";
    throw std::invalid_argument(s.str());
  }
  const size_t reach = std::min(reach_sleepers, soil.distanceCount() - 1);
  return [&soil, sleepers, reach](double frequency_hz) {
    std::vector<std::complex<double>> h(reach + 1);
    for (size_t k = 0; k <= reach; ++k) h[k] = track::kHalfTrackRailsOnSoil * soil.compliance(k, frequency_hz);
    const Eigen::Index n = static_cast<Eigen::Index>(sleepers);
    Eigen::MatrixXcd g = Eigen::MatrixXcd::Zero(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = std::max<Eigen::Index>(0, i - static_cast<Eigen::Index>(reach));
           j <= std::min<Eigen::Index>(n - 1, i + static_cast<Eigen::Index>(reach)); ++j) {
        g(i, j) = h[static_cast<size_t>(std::abs(i - j))];
      }
    }
    return g;
  };
}

std::vector<std::complex<double>> feSoilReceptance(const track::TrackParams& track_params,
                                                   const soil::FootprintCompliance& soil, double x_m,
                                                   const std::vector<double>& frequencies_hz, size_t reach_sleepers) {
  track::TrackParams rigid = track_params;
  rigid.foundation = track::FoundationModel::Rigid;  // the ballast's base is the soil's footprint
  const track::TrackModel model(rigid);
  return track::receptanceOnGround(
      model, x_m, frequencies_hz,
      feSoilGround(soil, rigid.layout.spacing_m, static_cast<size_t>(model.sleeperCount()), reach_sleepers));
}

}  // namespace railvib::coupling
