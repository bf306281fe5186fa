// Typical ranges of physical quantities, by the key that holds them: the unit-slip check of the
// configuration (a density in g/cm^3 written where kg/m^3 goes, a stiffness in MN/m where N/m goes).
// A key's own allowed range says what the model can compute; the typical range says what a real
// track, vehicle or soil has. A value inside the first and outside the second is refused unless its
// key is listed under `plausibility.accept` (a deliberate value, e.g. a rigid contact in a study).
#pragma once

#include <string>
#include <vector>

namespace railvib {

struct PlausibilityRule {
  /// A key name ending ("stiffness_n_m": also coupling_stiffness_n_m), or a path ending with a dot
  /// ("defect.height_m": the unevenness defect's height, not a storey's).
  std::string pattern;
  double typical_lo;  // of |value|; 0 itself is always typical (a quantity switched off)
  double typical_hi;
  std::string unit;
  std::string slip;  // the unit mistake a value outside suggests
};

/// A key path with its list indices as "[]" (soil.layers[2].thickness_m -> soil.layers[].thickness_m): the
/// form the rules and the configuration's record of read keys use.
std::string normalizedKeyPath(const std::string& path);

/// Every rule (one table: docs/robustness.md lists it).
const std::vector<PlausibilityRule>& plausibilityRules();

/// The rule for a key path (list indices allowed: "soil.layers[0].density_kg_m3"), or nullptr.
const PlausibilityRule* plausibilityRuleFor(const std::string& key_path);

/// True when |value| lies in the rule's typical range (or value is 0).
bool isTypical(const PlausibilityRule& rule, double value);

}  // namespace railvib
