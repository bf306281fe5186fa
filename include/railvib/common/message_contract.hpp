// railvib/common: the contract of the messages that are not streams (metrics, snapshots, transforms).
//
// A stream block proves its own continuity (stream_contract.hpp); a metrics message, a surface or
// section snapshot or a transform stands alone, so a publisher that is not railvib's (a test tool, a
// misconfigured monitor, a replay of another run) can put anything on those topics. Every reader
// (the recorder, the scene visualiser) checks each one here before it uses or records it; the
// Python readers (monitor, bag check) apply the same rules from scripts/railvib_contracts.py, and
// both are held to one table of cases (test/data/message_contract_cases.json).
//
// Each check throws StreamContractError naming the topic, the field, its value and the rule; it
// reads nothing out of bounds and allocates nothing from a message's counts.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "railvib/common/stream_contract.hpp"

namespace railvib {

/// What a VibrationMetrics message carries (msg/VibrationMetrics.msg), in SI units.
struct MetricsFields {
  std::string sensor_name;
  uint32_t kind = 0;  ///< 0 free field, 1 foundation, 2 floor
  double resolved_hz = 0.0;
  double kb_f = 0.0;
  double kb_f_max = 0.0;
  double ppv_m_s = 0.0;
  double ppv_vertical_m_s = 0.0;
  uint32_t governing_component = 0;
  double governing_ppv_m_s = 0.0;
  double dominant_frequency_hz = 0.0;
  double din4150_3_limit_m_s = 0.0;
  const std::vector<double>* third_octave_center_hz = nullptr;
  const std::vector<double>* third_octave_level_db = nullptr;
  uint32_t din4150_2_verdict = 0;
  double din4150_2_a_u = 0.0;
  double din4150_2_a_o = 0.0;
  double din4150_2_a_r = 0.0;
  uint32_t din4150_3_verdict = 0;
  uint32_t verdict = 0;
};

/// Most one-third octave bands a metrics message may carry (1 Hz to 20 kHz is 44).
inline constexpr size_t kMaxThirdOctaveBands = 64;
/// Most values a snapshot may carry (a 4000 x 4000 surface grid; the soil node sends ~1e4).
inline constexpr uint64_t kMaxSnapshotValues = 16000000;
/// Largest |translation| of a transform (m): the site is kilometres across, not more.
inline constexpr double kMaxTranslationM = 1.0e6;
/// Tolerance on the norm of a transform's rotation quaternion (tf2 refuses non-unit ones too).
inline constexpr double kQuaternionNormTolerance = 1.0e-3;

/// A metrics message: sensor name one of `known_sensors` (when not empty), codes within their
/// enumerations, every value finite and physically bounded (`limits.velocity_m_s`), the running
/// maxima not below the current values (KB_Fmax >= KB_F, vector PPV >= vertical and governing
/// component PPV), the DIN 4150-2 guide values ordered (A_u <= A_o), the bands as many as their
/// levels, at most kMaxThirdOctaveBands, centres increasing; a level may be -inf (no signal yet).
void validateMetrics(const std::string& topic, const MetricsFields& m, const StreamLimits& limits,
                     const std::vector<std::string>& known_sensors);

/// A snapshot's horizontal velocity fields (velocity_x_m_s, velocity_y_m_s; null = empty).
struct SnapshotHorizontal {
  const std::vector<float>* velocity_x_m_s = nullptr;
  const std::vector<float>* velocity_y_m_s = nullptr;
};

/// A surface snapshot: nx, ny >= 1, nx * ny <= kMaxSnapshotValues and equal to the values' count,
/// origin finite, spacing finite and positive, every value finite with |v| <= limits.velocity_m_s;
/// the horizontal fields both empty, or both as many values as the vertical and bounded alike.
void validateSurfaceSnapshot(const std::string& topic, double origin_x_m, double origin_y_m, double spacing_x_m,
                             double spacing_y_m, uint64_t nx, uint64_t ny, const std::vector<float>& values,
                             const StreamLimits& limits, const SnapshotHorizontal& horizontal);

/// A section snapshot: ny >= 1, depths finite, non-negative and increasing, depths x ny values
/// (within kMaxSnapshotValues), x and origin finite, spacing positive, values and horizontal
/// fields as above.
void validateSectionSnapshot(const std::string& topic, double x_m, double origin_y_m, double spacing_y_m, uint64_t ny,
                             const std::vector<double>& depth_m, const std::vector<float>& values,
                             const StreamLimits& limits, const SnapshotHorizontal& horizontal);

/// One transform: both frame names non-empty and different, translation finite within
/// kMaxTranslationM, rotation a finite unit quaternion (|q| within kQuaternionNormTolerance of 1).
void validateTransform(const std::string& topic, const std::string& parent_frame, const std::string& child_frame,
                       const double translation_m[3], const double rotation_xyzw[4]);

}  // namespace railvib
