// railvib/common: configuration loading and validation.
//
// One mechanism validates every parameter of the project. A scenario file
// (e.g. config/haren.yaml) may `include:` other files; included files are
// merged first, then the including file's own keys override them leaf by
// leaf, then command-line / roslaunch overrides ("a.b.c=value") override
// everything. Every leaf remembers the file it came from, so an error names
// the key path, the value, the allowed range and the file.
//
// Strictness: every file is at most kMaxConfigBytes, a map may not repeat a
// key, anchors and aliases are limited (kMaxAliasDepth, kMaxExpandedNodes; an
// alias never inside the value its anchor names, and each alias is a copy of
// that value, so an override changes one key path only), and every accessor of
// ConfigNode records the key it asked for, so Config::refuseUnknownKeys() can
// refuse what no loader knows (a typo) with the nearest valid key. A choice
// (e.g. `model: clm`) makes the sibling sections named after its other allowed
// values (`winkler:`) inactive alternatives: known, not read (unless a loader
// reads into one anyway: then its keys are checked like any other).
#pragma once

#include <yaml-cpp/yaml.h>

#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace railvib {

/// Raised for any invalid configuration; the message is user-facing.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Allowed interval of a scalar parameter (bounds may be open or infinite).
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = true;
  bool hi_open = true;

  static Range any() { return {}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, true}; }
  static Range nonNegative() { return {0.0, std::numeric_limits<double>::infinity(), false, true}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range open(double a, double b) { return {a, b, true, true}; }
  static Range atLeast(double a) { return {a, std::numeric_limits<double>::infinity(), false, true}; }
  static Range greaterThan(double a) { return {a, std::numeric_limits<double>::infinity(), true, true}; }
  static Range atMost(double b) { return {-std::numeric_limits<double>::infinity(), b, true, false}; }

  bool contains(double value) const;
  /// Interval notation, e.g. "(0, inf)" or "[0.1, 0.5)".
  std::string describe() const;
};

namespace detail {
struct ConfigData;
}

/// Limits on what a configuration may be (each file, and each override value).
constexpr size_t kMaxConfigBytes = 1 << 20;   // the whole Haren scenario is ~30 KB
constexpr int kMaxConfigNesting = 32;         // levels of maps and lists
constexpr int kMaxAliasDepth = 2;             // an alias of an anchor that holds aliases, no deeper
constexpr size_t kMaxExpandedNodes = 100000;  // nodes once every alias is expanded
/// No number of a scenario, in SI units, exceeds this magnitude (a Young's modulus is ~1e11 Pa; a
/// Hertz constant raised to make the contact rigid in a test is 1e16): whatever a key's own range,
/// a larger one (1e300) is refused.
constexpr double kMaxConfigMagnitude = 1e18;

/// A map node of the merged configuration, with its dotted key path.
class ConfigNode {
 public:
  ConfigNode(std::shared_ptr<const detail::ConfigData> data, YAML::Node node, std::string key_path);

  /// Dotted path of this node ("" for the root).
  const std::string& keyPath() const { return key_path_; }
  /// Dotted path of a child key.
  std::string childPath(const std::string& key) const;
  /// File a key (or, failing that, this section) was read from.
  std::string fileOf(const std::string& key) const;

  bool has(const std::string& key) const;
  /// Required sub-map.
  ConfigNode section(const std::string& key) const;
  /// Required list of maps.
  std::vector<ConfigNode> sectionList(const std::string& key) const;

  /// Required finite number within range.
  double number(const std::string& key, const Range& range) const;
  /// Optional finite number within range; default when absent.
  double number(const std::string& key, const Range& range, double default_value) const;
  /// Required integer within [lo, hi].
  long integer(const std::string& key, long lo, long hi) const;
  long integer(const std::string& key, long lo, long hi, long default_value) const;
  bool flag(const std::string& key) const;
  bool flag(const std::string& key, bool default_value) const;
  /// Required string that must be one of `allowed`.
  std::string choice(const std::string& key, const std::vector<std::string>& allowed) const;
  std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                     const std::string& default_value) const;
  /// Required non-empty string.
  std::string text(const std::string& key) const;
  std::string text(const std::string& key, const std::string& default_value) const;
  /// Required list of finite numbers, each within range, count in [min_count, max_count].
  std::vector<double> numbers(const std::string& key, const Range& range, size_t min_count = 0,
                              size_t max_count = std::numeric_limits<size_t>::max()) const;
  std::vector<std::string> texts(const std::string& key) const;
  /// A file path, resolved relative to the directory of the file that set it.
  std::string filePath(const std::string& key) const;

  /// Raise a ConfigError about `key` (consistency checks between values).
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const;

  /// The raw node. Reading it bypasses the key record: a loader that does must mark what it
  /// reads with markKnown().
  const YAML::Node& yaml() const { return node_; }
  /// Record `key` (and everything below it) as known without reading it.
  void markKnown(const std::string& key) const;

 private:
  void record(const std::string& key) const;
  YAML::Node required(const std::string& key) const;
  [[noreturn]] void failValue(const std::string& key, const YAML::Node& value, const std::string& reason) const;

  std::shared_ptr<const detail::ConfigData> data_;
  YAML::Node node_;
  std::string key_path_;
};

/// The merged configuration of a scenario.
class Config {
 public:
  /// Load a scenario file (following `include:`), then apply overrides of the
  /// form "key.path=value" (value parsed as YAML). Throws ConfigError.
  static Config load(const std::string& file, const std::vector<std::string>& overrides = {});
  /// Parse from a YAML string (tests); `label` stands for the file name.
  static Config fromString(const std::string& yaml_text, const std::string& label = "<string>");

  ConfigNode root() const;
  /// What the loading noticed that a reader should know (e.g. an override that dropped list entries).
  const std::vector<std::string>& notes() const;
  ConfigNode section(const std::string& key) const { return root().section(key); }
  /// The merged configuration as YAML text (recorded next to results).
  std::string dump() const;
  /// The scenario file this configuration was loaded from.
  const std::string& file() const;

  /// Keys present in the configuration that no accessor asked for (after every loader ran), each
  /// with the nearest valid key ("did you mean"), one line per key, in the error format.
  std::vector<std::string> unknownKeys() const;
  /// Throws ConfigError listing unknownKeys(), if any.
  void refuseUnknownKeys() const;

 private:
  explicit Config(std::shared_ptr<detail::ConfigData> data) : data_(std::move(data)) {}
  std::shared_ptr<detail::ConfigData> data_;
};

}  // namespace railvib
