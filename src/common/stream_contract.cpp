#include "railvib/common/stream_contract.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace railvib {

namespace {

[[noreturn]] void refuse(const std::string& stream, const std::string& what) {
  throw StreamContractError("stream " + stream + ": " + what);
}

std::string componentName(uint32_t component, uint32_t components) {
  if (components == 3) return std::string(1, "xyz"[component]);
  return "component " + std::to_string(component);
}

}  // namespace

std::string formatValue(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

StreamLimits loadStreamLimits(const ConfigNode& root) {
  StreamLimits l;
  if (!root.has("limits")) return l;
  const ConfigNode n = root.section("limits");
  const Range bound = Range::positive();
  l.contact_force_n = n.number("contact_force_n", bound, l.contact_force_n);
  l.wheel_position_m = n.number("wheel_position_m", bound, l.wheel_position_m);
  l.unevenness_m = n.number("unevenness_m", bound, l.unevenness_m);
  l.soil_load_n = n.number("soil_load_n", bound, l.soil_load_n);
  l.velocity_m_s = n.number("velocity_m_s", bound, l.velocity_m_s);
  l.acceleration_m_s2 = n.number("acceleration_m_s2", bound, l.acceleration_m_s2);
  l.max_block_samples = static_cast<uint32_t>(n.integer("max_block_samples", 1, 100000000L, l.max_block_samples));
  l.max_points = static_cast<uint32_t>(n.integer("max_points", 1, 100000000L, l.max_points));
  return l;
}

size_t firstValueOutside(const double* values, size_t n, double bound) {
  for (size_t i = 0; i < n; ++i) {
    // !(|v| <= bound) is also true for NaN.
    if (!(std::abs(values[i]) <= bound)) return i;
  }
  return n;
}

void validateBlock(const BlockContract& c, const BlockHead& h, std::initializer_list<BlockArray> arrays) {
  const std::string at = " (block at sample " + std::to_string(h.first_sample_index) + ")";
  if (!(std::isfinite(h.sample_period_s) && h.sample_period_s > 0.0)) {
    refuse(c.stream, "sample_period_s = " + formatValue(h.sample_period_s) + ": must be a finite positive period; " +
                         "expected " + formatValue(c.sample_period_s) + " s (" + c.period_source + ")" + at);
  }
  if (std::abs(h.sample_period_s - c.sample_period_s) > 1e-9 * c.sample_period_s) {
    refuse(c.stream, "sample_period_s = " + formatValue(h.sample_period_s) + ": differs from the configured " +
                         formatValue(c.sample_period_s) + " s (" + c.period_source + ")" + at);
  }
  if (h.point_count != c.point_count) {
    refuse(c.stream, c.count_field + " = " + std::to_string(h.point_count) + ": " + c.point_source + " has " +
                         std::to_string(c.point_count) + " " + c.point_label + "(s)" + at);
  }
  if (h.sample_count > c.max_block_samples) {
    refuse(c.stream, "sample_count = " + std::to_string(h.sample_count) + ": more than the " +
                         std::to_string(c.max_block_samples) + " samples a block may hold (limits.max_block_samples)" +
                         at);
  }
  if (h.first_sample_index > std::numeric_limits<uint64_t>::max() - h.sample_count) {
    refuse(c.stream, "first_sample_index = " + std::to_string(h.first_sample_index) +
                         ": the block would run past the largest sample index");
  }
  // Both factors are bounded above (max_block_samples, the layout's count): no overflow.
  for (const BlockArray& a : arrays) {
    const uint64_t per_sample = static_cast<uint64_t>(h.point_count) * a.components;
    const uint64_t expected = static_cast<uint64_t>(h.sample_count) * per_sample;
    if (a.values->size() != expected) {
      const std::string x3 = a.components > 1 ? " x " + std::to_string(a.components) : "";
      refuse(c.stream, std::string(a.field) + " has " + std::to_string(a.values->size()) +
                           " values, not sample_count x " + c.count_field + x3 + " = " +
                           std::to_string(h.sample_count) + " x " + std::to_string(h.point_count) + x3 + " = " +
                           std::to_string(expected) + at);
    }
  }
  for (const BlockArray& a : arrays) {
    const size_t i = firstValueOutside(a.values->data(), a.values->size(), a.bound);
    if (i == a.values->size()) continue;
    const size_t per_sample = static_cast<size_t>(h.point_count) * a.components;
    const size_t sample = i / per_sample;
    const uint32_t point = static_cast<uint32_t>((i % per_sample) / a.components);
    const uint32_t component = static_cast<uint32_t>(i % a.components);
    std::string where =
        "sample " + std::to_string(h.first_sample_index + sample) + ", " + c.point_label + " " + std::to_string(point);
    if (a.components > 1) where += ", " + componentName(component, a.components);
    refuse(c.stream, std::string(a.field) + "[" + where + "] = " + formatValue((*a.values)[i]) +
                         ": must be finite with magnitude <= " + formatValue(a.bound) + " " + a.unit + " (" +
                         a.bound_source + ")");
  }
}

void validatePointCodes(const BlockContract& c, const char* field, const std::vector<uint8_t>& codes,
                        const std::vector<uint8_t>& expected, const std::string& expected_source) {
  if (codes.size() != expected.size()) {
    refuse(c.stream, std::string(field) + " has " + std::to_string(codes.size()) + " values, not one per " +
                         c.point_label + " (" + std::to_string(expected.size()) + ", " + expected_source + ")");
  }
  for (size_t i = 0; i < codes.size(); ++i) {
    if (codes[i] != expected[i]) {
      refuse(c.stream, std::string(field) + "[" + std::to_string(i) + "] = " + std::to_string(codes[i]) + ": " +
                           expected_source + " has " + std::to_string(expected[i]) + " for " + c.point_label + " " +
                           std::to_string(i));
    }
  }
}

void validatePointLayout(const std::string& topic, const std::vector<std::string>& names, size_t positions,
                         const std::vector<double>& coordinates, uint32_t max_points) {
  if (names.empty() || names.size() > max_points) {
    refuse(topic, "holds " + std::to_string(names.size()) + " points; between 1 and " + std::to_string(max_points) +
                      " expected (limits.max_points)");
  }
  if (positions != names.size()) {
    refuse(topic, std::to_string(names.size()) + " names but " + std::to_string(positions) + " positions");
  }
  std::set<std::string> seen;
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) refuse(topic, "names[" + std::to_string(i) + "] is empty");
    if (!seen.insert(names[i]).second) refuse(topic, "names[" + std::to_string(i) + "] = '" + names[i] + "' repeats");
  }
  const size_t bad = firstValueOutside(coordinates.data(), coordinates.size(), 1.0e6);
  if (bad < coordinates.size()) {
    refuse(topic, "positions[" + std::to_string(bad / 3) + "] ('" + names[std::min(bad / 3, names.size() - 1)] + "')." +
                      std::string(1, "xyz"[bad % 3]) + " = " + formatValue(coordinates[bad]) +
                      ": must be finite, within 1e6 m");
  }
}

void validateSleeperPositions(const std::string& topic, const std::vector<double>& x_m, uint32_t max_points) {
  if (x_m.empty() || x_m.size() > max_points) {
    refuse(topic, "holds " + std::to_string(x_m.size()) + " sleepers; between 1 and " + std::to_string(max_points) +
                      " expected (limits.max_points)");
  }
  for (size_t i = 0; i < x_m.size(); ++i) {
    if (!std::isfinite(x_m[i])) refuse(topic, "position_m[" + std::to_string(i) + "] = " + formatValue(x_m[i]));
    if (i > 0 && !(x_m[i] > x_m[i - 1])) {
      refuse(topic, "position_m[" + std::to_string(i) + "] = " + formatValue(x_m[i]) +
                        ": sleeper positions must increase (previous " + formatValue(x_m[i - 1]) + ")");
    }
  }
}

}  // namespace railvib
