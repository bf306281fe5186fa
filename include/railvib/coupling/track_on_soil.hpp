// railvib/coupling: the track standing on the FE soil, in the frequency domain (paper, section 2.2
// and Fig. 4): the rail receptance of the "rigorous" track-soil model that the CLM foundation
// approximates. The track domain solves a rail whose ballast stands on any ground given by its
// compliance between the sleepers (track::receptanceOnGround); the soil domain gives the FE soil's
// compliance between footprints from one impulse run (soil::FootprintCompliance); this file joins
// them: translation invariance along the track, both rails on each footprint.
#pragma once

#include <complex>
#include <cstddef>
#include <limits>
#include <vector>

#include "railvib/soil/footprint_compliance.hpp"
#include "railvib/track/track_analysis.hpp"

namespace railvib::coupling {

/// The ground under a half track of `sleepers` sleepers from the FE soil's footprint compliance:
/// G_ij(f) = kHalfTrackRailsOnSoil H_|i-j|(f) (both rails load each footprint alike) for |i - j| up
/// to the run's reach and `reach_sleepers`, 0 beyond (the soil's coupling between sleepers further
/// apart is left out: docs/validation.md gives the effect of the reach). Throws
/// std::invalid_argument when the soil run's sleeper spacing is not the track's.
track::GroundCompliance feSoilGround(const soil::FootprintCompliance& soil, double track_spacing_m, size_t sleepers,
                                     size_t reach_sleepers = std::numeric_limits<size_t>::max());

/// The rail receptance at x_m of the scenario's track (rail, railpads, sleepers, ballast: the
/// `track` section, half width) on the FE soil of the same scenario (the `soil` section: layers,
/// mesh, boundary, damping), for the frequencies given (up to the mesh's f_max). The soil run is
/// the expensive part (a minute on the Haren mesh): build it once, soil::FootprintCompliance(
/// soil::loadSoilParams(root), spec), and pass it in.
std::vector<std::complex<double>> feSoilReceptance(const track::TrackParams& track,
                                                   const soil::FootprintCompliance& soil, double x_m,
                                                   const std::vector<double>& frequencies_hz,
                                                   size_t reach_sleepers = std::numeric_limits<size_t>::max());

}  // namespace railvib::coupling
