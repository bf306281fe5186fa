// railvib/common: the contract of a stream block, checked by every consumer before it uses one.
//
// A block (ContactForces, SoilLoads, SurfaceVelocities, BuildingResponse, SensorSamples) carries
// its own counts, period and arrays; none of them is trusted. validateBlock() checks, in this
// order, the period against the configured one, the point count against the layout, the sample
// count against a bound, the index range against overflow, every array's size against
// sample_count x point_count x components (without overflow), and every value: finite and within
// the physical bound of the `limits` section (StreamLimits). A violation throws StreamContractError
// naming the stream, the field, the value, the expected value or bound, and the sample; nothing is
// read out of bounds. The same value check serves the file readers (loads CSV, profiles).
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"

namespace railvib {

class StreamContractError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Physical bounds of what the streams carry (`limits` section, all optional; the defaults are
/// the documented values of config/haren.yaml). A value beyond its bound is refused, not clipped.
struct StreamLimits {
  double contact_force_n = 1.0e6;        ///< |wheel/rail contact force|, one rail
  double wheel_position_m = 1.0e5;       ///< |wheel position along the track|
  double unevenness_m = 0.1;             ///< |rail unevenness under a wheel|
  double soil_load_n = 2.0e6;            ///< |ballast-to-soil force| per sleeper, both rails
  double velocity_m_s = 10.0;            ///< |soil or building particle velocity| per component
  double acceleration_m_s2 = 1.0e5;      ///< |sensor acceleration| per component
  uint32_t max_block_samples = 1000000;  ///< samples in one block
  uint32_t max_points = 1000000;         ///< wheels, sleepers, receivers or points in one block
};

/// Read the `limits` section (absent: the defaults). Throws ConfigError.
StreamLimits loadStreamLimits(const ConfigNode& root);

/// What a consumer expects of a stream: from its config and its latched layout.
struct BlockContract {
  std::string stream;            ///< topic, e.g. "/soil_loads"
  double sample_period_s = 0.0;  ///< expected period (> 0)
  std::string period_source;     ///< where the period comes from, e.g. "track.output.load_sample_rate_hz = 2000 Hz"
  std::string count_field;       ///< name of the message's point count field, e.g. "sleeper_count"
  std::string point_label;       ///< one point, e.g. "sleeper"
  uint32_t point_count = 0;      ///< from the layout (or the config)
  std::string point_source;      ///< where that count comes from, e.g. "the sleeper_layout"
  uint32_t max_block_samples = 1000000;
};

/// The common head of a stream block.
struct BlockHead {
  uint64_t first_sample_index = 0;
  bool end_of_stream = false;
  double sample_period_s = 0.0;
  uint32_t sample_count = 0;
  uint32_t point_count = 0;
};

/// One array of a block: `components` values per point and sample, each |v| <= bound.
struct BlockArray {
  const char* field;
  const std::vector<double>* values;
  uint32_t components;
  double bound;
  const char* bound_source;  ///< e.g. "limits.soil_load_n"
  const char* unit;
};

/// Throws StreamContractError on the first violation (see the file comment).
void validateBlock(const BlockContract& contract, const BlockHead& head, std::initializer_list<BlockArray> arrays);

/// A per-point code array of a block (e.g. ContactForces.wheel_rail) must be, code for code, what the
/// consumer's config says (`expected`, from `expected_source`). Throws StreamContractError.
void validatePointCodes(const BlockContract& contract, const char* field, const std::vector<uint8_t>& codes,
                        const std::vector<uint8_t>& expected, const std::string& expected_source);

/// Index of the first value that is not finite or whose magnitude exceeds `bound`; n if none.
size_t firstValueOutside(const double* values, size_t n, double bound);

/// "1e+300", "nan", "-inf": a value as a message shows it (17 significant digits at most).
std::string formatValue(double v);

/// Checks of a latched layout: count within [1, max], names unique and non-empty, coordinates
/// finite. Throws StreamContractError naming `topic`.
void validatePointLayout(const std::string& topic, const std::vector<std::string>& names, size_t positions,
                         const std::vector<double>& coordinates, uint32_t max_points);
/// Sleeper x positions: finite, strictly increasing, count within [1, max].
void validateSleeperPositions(const std::string& topic, const std::vector<double>& x_m, uint32_t max_points);

}  // namespace railvib
