#include "railvib/common/message_contract.hpp"

#include <algorithm>
#include <cmath>

namespace railvib {

namespace {

[[noreturn]] void refuse(const std::string& topic, const std::string& what) {
  throw StreamContractError("topic " + topic + ": " + what);
}

// Running maxima are taken over the same samples as the current values: equal within rounding.
bool atMost(double value, double maximum) { return value <= maximum * (1.0 + 1e-9) + 1e-15; }

void requireFinite(const std::string& topic, const char* field, double value, double lo, double hi,
                   const std::string& why) {
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    refuse(topic, std::string(field) + " = " + formatValue(value) + ": must be finite within [" + formatValue(lo) +
                      ", " + formatValue(hi) + "]" + (why.empty() ? "" : " (" + why + ")"));
  }
}

void requireCode(const std::string& topic, const char* field, uint32_t code, uint32_t largest, const char* meaning) {
  if (code > largest) {
    refuse(topic, std::string(field) + " = " + std::to_string(code) + ": not one of 0.." + std::to_string(largest) +
                      " (" + meaning + ")");
  }
}

template <typename T>
void requireValuesWithin(const std::string& topic, const char* field, const std::vector<T>& values, double bound,
                         const char* bound_source) {
  for (size_t i = 0; i < values.size(); ++i) {
    const double v = static_cast<double>(values[i]);
    if (!(std::abs(v) <= bound)) {
      refuse(topic, std::string(field) + "[" + std::to_string(i) + "] = " + formatValue(v) +
                        ": must be finite with magnitude <= " + formatValue(bound) + " m/s (" + bound_source + ")");
    }
  }
}

void requireSpacing(const std::string& topic, const char* field, double spacing_m) {
  requireFinite(topic, field, spacing_m, 1e-9, kMaxTranslationM, "a grid spacing in m, positive");
}

}  // namespace

void validateMetrics(const std::string& topic, const MetricsFields& m, const StreamLimits& limits,
                     const std::vector<std::string>& known_sensors) {
  if (m.sensor_name.empty()) refuse(topic, "sensor_name is empty");
  if (!known_sensors.empty() &&
      std::find(known_sensors.begin(), known_sensors.end(), m.sensor_name) == known_sensors.end()) {
    std::string list;
    for (const auto& s : known_sensors) list += (list.empty() ? "" : ", ") + s;
    refuse(topic, "sensor_name '" + m.sensor_name + "' is not a sensor of the scenario (" + list + ")");
  }
  requireCode(topic, "kind", m.kind, 2, "free field, foundation, floor");
  requireCode(topic, "governing_component", m.governing_component, 2, "x, y, z");
  for (const auto& [field, code] : {std::pair<const char*, uint32_t>{"din4150_2_verdict", m.din4150_2_verdict},
                                    {"din4150_3_verdict", m.din4150_3_verdict},
                                    {"verdict", m.verdict}}) {
    requireCode(topic, field, code, 4, "OK, WARN, ERROR, NOT_APPLICABLE, NOT_ASSESSABLE");
  }
  const double velocity = limits.velocity_m_s;
  const std::string velocity_why = "limits.velocity_m_s = " + formatValue(velocity) + " per component";
  requireFinite(topic, "resolved_hz", m.resolved_hz, 0.0, 1e5, "a frequency in Hz");
  // KB_F is the weighted velocity in mm/s (DIN 4150-2): bounded by the velocity bound, with room for
  // the weighting filter's transient overshoot.
  const double kb_bound = 2.0 * 1e3 * velocity;
  requireFinite(topic, "kb_f", m.kb_f, 0.0, kb_bound, "2 x limits.velocity_m_s in mm/s");
  requireFinite(topic, "kb_f_max", m.kb_f_max, 0.0, kb_bound, "2 x limits.velocity_m_s in mm/s");
  if (!atMost(m.kb_f, m.kb_f_max)) {
    refuse(topic,
           "kb_f = " + formatValue(m.kb_f) + " exceeds its running maximum kb_f_max = " + formatValue(m.kb_f_max));
  }
  const double vector_bound = std::sqrt(3.0) * velocity;
  requireFinite(topic, "ppv_m_s", m.ppv_m_s, 0.0, vector_bound, "sqrt(3) x " + velocity_why);
  requireFinite(topic, "ppv_vertical_m_s", m.ppv_vertical_m_s, 0.0, velocity, velocity_why);
  requireFinite(topic, "governing_ppv_m_s", m.governing_ppv_m_s, 0.0, velocity, velocity_why);
  for (const auto& [field, value] : {std::pair<const char*, double>{"ppv_vertical_m_s", m.ppv_vertical_m_s},
                                     {"governing_ppv_m_s", m.governing_ppv_m_s}}) {
    if (!atMost(value, m.ppv_m_s)) {
      refuse(topic, std::string(field) + " = " + formatValue(value) + " exceeds the vector peak ppv_m_s = " +
                        formatValue(m.ppv_m_s) + " (a component's peak cannot)");
    }
  }
  requireFinite(topic, "dominant_frequency_hz", m.dominant_frequency_hz, 0.0, 1e5, "a frequency in Hz");
  requireFinite(topic, "din4150_3_limit_m_s", m.din4150_3_limit_m_s, 0.0, velocity, velocity_why);
  requireFinite(topic, "din4150_2_a_u", m.din4150_2_a_u, 0.0, 1e3, "a DIN 4150-2 guide value");
  requireFinite(topic, "din4150_2_a_o", m.din4150_2_a_o, 0.0, 1e3, "a DIN 4150-2 guide value");
  requireFinite(topic, "din4150_2_a_r", m.din4150_2_a_r, 0.0, 1e3, "a DIN 4150-2 guide value");
  if (m.din4150_2_a_u > m.din4150_2_a_o) {
    refuse(topic, "din4150_2_a_u = " + formatValue(m.din4150_2_a_u) +
                      " exceeds din4150_2_a_o = " + formatValue(m.din4150_2_a_o) + " (DIN 4150-2 Table 1: A_u < A_o)");
  }
  static const std::vector<double> kNone;
  const std::vector<double>& centres = m.third_octave_center_hz ? *m.third_octave_center_hz : kNone;
  const std::vector<double>& levels = m.third_octave_level_db ? *m.third_octave_level_db : kNone;
  if (centres.size() > kMaxThirdOctaveBands) {
    refuse(topic, "third_octave_center_hz has " + std::to_string(centres.size()) + " bands; at most " +
                      std::to_string(kMaxThirdOctaveBands));
  }
  if (levels.size() != centres.size()) {
    refuse(topic, "third_octave_level_db has " + std::to_string(levels.size()) + " values for " +
                      std::to_string(centres.size()) + " band centres");
  }
  for (size_t b = 0; b < centres.size(); ++b) {
    if (!(std::isfinite(centres[b]) && centres[b] > 0.0 && centres[b] <= 1e5) ||
        (b > 0 && centres[b] <= centres[b - 1])) {
      refuse(topic, "third_octave_center_hz[" + std::to_string(b) + "] = " + formatValue(centres[b]) +
                        ": band centres must be finite, positive (Hz) and increasing");
    }
  }
  // A level re 1e-9 m/s (ISO 1683) of the velocity bound, with room for the band filters' gain.
  const double level_bound_db = 20.0 * std::log10(velocity / 1e-9) + 20.0;
  for (size_t b = 0; b < levels.size(); ++b) {
    const double l = levels[b];
    // -inf: nothing in the band yet (the running mean square is 0).
    if (std::isnan(l) || l > level_bound_db) {
      refuse(topic, "third_octave_level_db[" + std::to_string(b) + "] = " + formatValue(l) +
                        ": must be a level in dB re 1e-9 m/s, at most " + formatValue(level_bound_db) +
                        " (limits.velocity_m_s + 20 dB)");
    }
  }
}

namespace {
// The horizontal fields of a snapshot: both empty (vertical only) or both laid out as the vertical.
void requireHorizontal(const std::string& topic, const SnapshotHorizontal& horizontal, uint64_t count,
                       const StreamLimits& limits) {
  const std::vector<float>* fields[2] = {horizontal.velocity_x_m_s, horizontal.velocity_y_m_s};
  const char* field_names[2] = {"velocity_x_m_s", "velocity_y_m_s"};
  const size_t nx_values = fields[0] ? fields[0]->size() : 0, ny_values = fields[1] ? fields[1]->size() : 0;
  if (nx_values == 0 && ny_values == 0) return;
  for (int c = 0; c < 2; ++c) {
    const size_t n = fields[c] ? fields[c]->size() : 0;
    if (n != count) {
      refuse(topic, std::string(field_names[c]) + " has " + std::to_string(n) + " values, not " +
                        std::to_string(count) + " as vertical_velocity_m_s (or both horizontal fields empty)");
    }
    requireValuesWithin(topic, field_names[c], *fields[c], limits.velocity_m_s, "limits.velocity_m_s");
  }
}
}  // namespace

void validateSurfaceSnapshot(const std::string& topic, double origin_x_m, double origin_y_m, double spacing_x_m,
                             double spacing_y_m, uint64_t nx, uint64_t ny, const std::vector<float>& values,
                             const StreamLimits& limits, const SnapshotHorizontal& horizontal) {
  if (nx < 1 || ny < 1 || nx > kMaxSnapshotValues || ny > kMaxSnapshotValues || nx * ny > kMaxSnapshotValues) {
    refuse(topic, "a " + std::to_string(nx) + " x " + std::to_string(ny) +
                      " grid: nx and ny must be >= 1 with nx x ny <= " + std::to_string(kMaxSnapshotValues));
  }
  if (values.size() != nx * ny) {
    refuse(topic, "vertical_velocity_m_s has " + std::to_string(values.size()) + " values, not nx x ny = " +
                      std::to_string(nx) + " x " + std::to_string(ny) + " = " + std::to_string(nx * ny));
  }
  requireFinite(topic, "origin_x_m", origin_x_m, -kMaxTranslationM, kMaxTranslationM, "frame track");
  requireFinite(topic, "origin_y_m", origin_y_m, -kMaxTranslationM, kMaxTranslationM, "frame track");
  requireSpacing(topic, "spacing_x_m", spacing_x_m);
  requireSpacing(topic, "spacing_y_m", spacing_y_m);
  requireValuesWithin(topic, "vertical_velocity_m_s", values, limits.velocity_m_s, "limits.velocity_m_s");
  requireHorizontal(topic, horizontal, nx * ny, limits);
}

void validateSectionSnapshot(const std::string& topic, double x_m, double origin_y_m, double spacing_y_m, uint64_t ny,
                             const std::vector<double>& depth_m, const std::vector<float>& values,
                             const StreamLimits& limits, const SnapshotHorizontal& horizontal) {
  const uint64_t rows = depth_m.size();
  if (ny < 1 || rows < 1 || ny > kMaxSnapshotValues || rows * ny > kMaxSnapshotValues) {
    refuse(topic, "a section of " + std::to_string(rows) + " depths (depth_m) x ny = " + std::to_string(ny) +
                      " columns: both must be >= 1 with their product <= " + std::to_string(kMaxSnapshotValues));
  }
  if (values.size() != rows * ny) {
    refuse(topic, "vertical_velocity_m_s has " + std::to_string(values.size()) + " values, not depths x ny = " +
                      std::to_string(rows) + " x " + std::to_string(ny) + " = " + std::to_string(rows * ny));
  }
  requireFinite(topic, "x_m", x_m, -kMaxTranslationM, kMaxTranslationM, "frame track");
  requireFinite(topic, "origin_y_m", origin_y_m, -kMaxTranslationM, kMaxTranslationM, "frame track");
  requireSpacing(topic, "spacing_y_m", spacing_y_m);
  for (size_t r = 0; r < rows; ++r) {
    if (!(std::isfinite(depth_m[r]) && depth_m[r] >= 0.0 && depth_m[r] <= kMaxTranslationM) ||
        (r > 0 && depth_m[r] <= depth_m[r - 1])) {
      refuse(topic, "depth_m[" + std::to_string(r) + "] = " + formatValue(depth_m[r]) +
                        ": depths must be finite, >= 0 (m below the surface) and increasing");
    }
  }
  requireValuesWithin(topic, "vertical_velocity_m_s", values, limits.velocity_m_s, "limits.velocity_m_s");
  requireHorizontal(topic, horizontal, rows * ny, limits);
}

void validateTransform(const std::string& topic, const std::string& parent_frame, const std::string& child_frame,
                       const double translation_m[3], const double rotation_xyzw[4]) {
  if (parent_frame.empty() || child_frame.empty()) {
    refuse(topic, "a transform '" + parent_frame + "' -> '" + child_frame + "' with an empty frame name");
  }
  const std::string what = "transform '" + parent_frame + "' -> '" + child_frame + "': ";
  if (parent_frame == child_frame) refuse(topic, what + "a frame cannot be its own parent");
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(translation_m[i]) <= kMaxTranslationM)) {
      refuse(topic, what + "translation." + std::string(1, "xyz"[i]) + " = " + formatValue(translation_m[i]) +
                        " m: must be finite within " + formatValue(kMaxTranslationM) + " m");
    }
  }
  double norm_squared = 0.0;
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(rotation_xyzw[i])) {
      refuse(topic, what + "rotation." + std::string(1, "xyzw"[i]) + " = " + formatValue(rotation_xyzw[i]) +
                        ": must be finite");
    }
    norm_squared += rotation_xyzw[i] * rotation_xyzw[i];
  }
  const double norm = std::sqrt(norm_squared);
  if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
    refuse(topic, what + "rotation quaternion has norm " + formatValue(norm) + ": not a rotation (|q| = 1 within " +
                      formatValue(kQuaternionNormTolerance) + ")");
  }
}

}  // namespace railvib
