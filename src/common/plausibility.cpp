#include "railvib/common/plausibility.hpp"

#include <cmath>

namespace railvib {

// The bounds hold every real case with a margin (and the repository's test and study values): EPS
// geofoam 15-30 kg/m^3 to lead 11 340 kg/m^3; soft soil ~1e6 Pa to steel 2.1e11 Pa; rail pads
// 2e7-1e9 N/m and a rigid contact in a test 1e13 N/m; Hertz constants ~1e11 N/m^1.5 (1e16 rigid);
// rail EI 4.2e6 N m^2 (UIC60 6.4e6); rail mass 40-70 kg/m; tram to high speed 0.1-100 m/s.
const std::vector<PlausibilityRule>& plausibilityRules() {
  static const std::vector<PlausibilityRule> rules = {
      {"density_kg_m3", 10.0, 25000.0, "kg/m^3", "a density in g/cm^3 or t/m^3 is 1000 x smaller"},
      {"modulus_pa", 1.0e4, 1.0e12, "Pa", "a modulus in kPa, MPa or GPa is 1e3, 1e6 or 1e9 x smaller"},
      {"stiffness_n_m", 1.0e3, 1.0e14, "N/m", "a stiffness in kN/m or MN/m is 1e3 or 1e6 x smaller"},
      {"damping_n_s_m", 1.0, 1.0e9, "N s/m", "a damping in kN s/m is 1000 x smaller"},
      {"hertz_constant_n_m1_5", 1.0e9, 1.0e17, "N/m^1.5", "a Hertz constant in N/mm^1.5 is ~3e4 x smaller"},
      {"bending_stiffness_n_m2", 1.0e4, 1.0e10, "N m^2",
       "a bending stiffness in kN m^2 is 1000 x smaller, in N mm^2 1e6 x larger"},
      {"mass_per_length_kg_m", 1.0, 1000.0, "kg/m", "a mass per length in t/m is 1000 x smaller"},
      {"speed_m_s", 0.1, 150.0, "m/s", "a speed in km/h is 3.6 x larger"},
      {"time_step_s", 1.0e-8, 1.0e-2, "s", "a time step in ms or us is 1e3 or 1e6 x larger"},
      {"defect.height_m", 1.0e-6, 0.05, "m", "a defect height in mm is 1000 x larger"},
      {"defect.length_m", 0.005, 20.0, "m", "a defect length in mm is 1000 x larger"},
      {"layers[].thickness_m", 0.01, 500.0, "m", "a layer thickness in cm or mm is 100 or 1000 x larger"},
      {"mass_kg", 1.0e-3, 1.0e6, "kg", "a mass in g is 1000 x larger, in t 1000 x smaller"},
  };
  return rules;
}

namespace {
bool endsWith(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}
}  // namespace

std::string normalizedKeyPath(const std::string& path) {
  std::string out;
  out.reserve(path.size());
  for (size_t i = 0; i < path.size(); ++i) {
    out += path[i];
    if (path[i] == '[') {
      while (i + 1 < path.size() && path[i + 1] != ']') ++i;
    }
  }
  return out;
}

const PlausibilityRule* plausibilityRuleFor(const std::string& key_path) {
  const std::string path = normalizedKeyPath(key_path);
  const auto dot = path.rfind('.');
  const std::string name = dot == std::string::npos ? path : path.substr(dot + 1);
  for (const auto& rule : plausibilityRules()) {
    if (rule.pattern.find('.') != std::string::npos) {
      if (path == rule.pattern || endsWith(path, "." + rule.pattern)) return &rule;
    } else if (endsWith(name, rule.pattern)) {
      return &rule;
    }
  }
  return nullptr;
}

bool isTypical(const PlausibilityRule& rule, double value) {
  const double magnitude = std::abs(value);
  return magnitude == 0.0 || (magnitude >= rule.typical_lo && magnitude <= rule.typical_hi);
}

}  // namespace railvib
