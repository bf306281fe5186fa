#include "railvib/common/config.hpp"

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace railvib {

namespace detail {
struct ConfigData {
  YAML::Node root;
  std::string file;
  // leaf or section key path -> file that set it
  std::map<std::string, std::string> sources;
};
}  // namespace detail

namespace {

std::string formatBound(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string joinPath(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string describeValue(const YAML::Node& value) {
  if (!value.IsDefined() || value.IsNull()) return "(missing)";
  YAML::Emitter out;
  out << YAML::Flow << value;
  std::string text = out.c_str();
  if (text.size() > 80) text = text.substr(0, 77) + "...";
  return text;
}

// Record the source file of every node below `node`.
void recordSources(const YAML::Node& node, const std::string& path, const std::string& file,
                   std::map<std::string, std::string>& sources) {
  if (!path.empty()) sources[path] = file;
  if (node.IsMap()) {
    for (const auto& kv : node) {
      recordSources(kv.second, joinPath(path, kv.first.as<std::string>()), file, sources);
    }
  }
}

// Deep merge `overlay` onto `base` (maps merge by key; anything else replaces).
YAML::Node deepMerge(const YAML::Node& base, const YAML::Node& overlay) {
  if (!base.IsMap() || !overlay.IsMap()) return YAML::Clone(overlay);
  YAML::Node result = YAML::Clone(base);
  for (const auto& kv : overlay) {
    const std::string key = kv.first.as<std::string>();
    if (result[key]) {
      result[key] = deepMerge(result[key], kv.second);
    } else {
      result[key] = YAML::Clone(kv.second);
    }
  }
  return result;
}

YAML::Node loadFileRecursive(const fs::path& file, std::map<std::string, std::string>& sources,
                             std::vector<fs::path>& stack) {
  const fs::path canonical = fs::weakly_canonical(file);
  for (const auto& open : stack) {
    if (open == canonical) {
      throw ConfigError("config error: include cycle through " + canonical.string());
    }
  }
  if (!fs::exists(canonical)) {
    throw ConfigError("config error: file not found: " + file.string());
  }
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(canonical.string());
  } catch (const YAML::Exception& e) {
    throw ConfigError("config error in " + canonical.string() + ": not valid YAML: " + e.what());
  }
  if (doc.IsNull()) doc = YAML::Node(YAML::NodeType::Map);
  if (!doc.IsMap()) {
    throw ConfigError("config error in " + canonical.string() + ": top level must be a map of sections");
  }
  stack.push_back(canonical);
  YAML::Node merged(YAML::NodeType::Map);
  if (doc["include"]) {
    const YAML::Node includes = doc["include"];
    if (!includes.IsSequence()) {
      throw ConfigError("config error in " + canonical.string() + ": include = " + describeValue(includes) +
                        ": must be a list of file names");
    }
    for (const auto& inc : includes) {
      const fs::path inc_path = canonical.parent_path() / inc.as<std::string>();
      merged = deepMerge(merged, loadFileRecursive(inc_path, sources, stack));
    }
    doc.remove("include");
  }
  recordSources(doc, "", canonical.string(), sources);
  merged = deepMerge(merged, doc);
  stack.pop_back();
  return merged;
}

void applyOverride(detail::ConfigData& data, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ConfigError("config error: override '" + assignment + "' must look like key.path=value");
  }
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw ConfigError("config error: override '" + assignment + "': value is not valid YAML");
  }
  // Walk and create maps along the path. yaml-cpp node assignment rebinds
  // references, so rebuild the chain from the leaf upwards.
  std::vector<std::string> keys;
  std::stringstream ss(path);
  for (std::string k; std::getline(ss, k, '.');) {
    if (k.empty()) throw ConfigError("config error: override '" + assignment + "': empty key in path");
    keys.push_back(k);
  }
  YAML::Node overlay = value;
  for (auto it = keys.rbegin(); it != keys.rend(); ++it) {
    YAML::Node parent(YAML::NodeType::Map);
    parent[*it] = overlay;
    overlay = parent;
  }
  data.root = deepMerge(data.root, overlay);
  recordSources(overlay, "", "command-line override '" + assignment + "'", data.sources);
}

}  // namespace

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::describe() const {
  return std::string(lo_open ? "(" : "[") + formatBound(lo) + ", " + formatBound(hi) + (hi_open ? ")" : "]");
}

ConfigNode::ConfigNode(std::shared_ptr<const detail::ConfigData> data, YAML::Node node, std::string key_path)
    : data_(std::move(data)), node_(std::move(node)), key_path_(std::move(key_path)) {}

std::string ConfigNode::childPath(const std::string& key) const { return joinPath(key_path_, key); }

std::string ConfigNode::fileOf(const std::string& key) const {
  // The most specific recorded path wins: the key itself, else the nearest parent.
  std::string path = key.empty() ? key_path_ : childPath(key);
  while (true) {
    auto it = data_->sources.find(path);
    if (it != data_->sources.end()) return it->second;
    const auto dot = path.rfind('.');
    if (dot == std::string::npos) break;
    path = path.substr(0, dot);
  }
  auto it = data_->sources.find(path);
  return it != data_->sources.end() ? it->second : data_->file;
}

void ConfigNode::fail(const std::string& key, const std::string& reason) const {
  YAML::Node value = node_.IsMap() && node_[key] ? node_[key] : YAML::Node();
  failValue(key, value, reason);
}

void ConfigNode::failValue(const std::string& key, const YAML::Node& value, const std::string& reason) const {
  throw ConfigError("config error: " + childPath(key) + " = " + describeValue(value) + ": " + reason + " [file " +
                    fileOf(key) + "]");
}

bool ConfigNode::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
}

YAML::Node ConfigNode::required(const std::string& key) const {
  if (!has(key)) failValue(key, YAML::Node(), "required key is missing");
  return node_[key];
}

ConfigNode ConfigNode::section(const std::string& key) const {
  YAML::Node child = required(key);
  if (!child.IsMap()) failValue(key, child, "must be a map (section)");
  return ConfigNode(data_, child, childPath(key));
}

std::vector<ConfigNode> ConfigNode::sectionList(const std::string& key) const {
  YAML::Node child = required(key);
  if (!child.IsSequence()) failValue(key, child, "must be a list");
  std::vector<ConfigNode> out;
  for (size_t i = 0; i < child.size(); ++i) {
    if (!child[i].IsMap()) failValue(key, child, "entry " + std::to_string(i) + " must be a map");
    out.emplace_back(data_, child[i], childPath(key) + "[" + std::to_string(i) + "]");
  }
  return out;
}

double ConfigNode::number(const std::string& key, const Range& range) const {
  YAML::Node value = required(key);
  double v = 0.0;
  if (!value.IsScalar()) failValue(key, value, "must be a number");
  try {
    v = value.as<double>();
  } catch (const YAML::Exception&) {
    failValue(key, value, "must be a number");
  }
  if (!std::isfinite(v)) failValue(key, value, "must be a finite number; allowed range " + range.describe());
  if (!range.contains(v)) failValue(key, value, "out of range; allowed range " + range.describe());
  return v;
}

double ConfigNode::number(const std::string& key, const Range& range, double default_value) const {
  return has(key) ? number(key, range) : default_value;
}

long ConfigNode::integer(const std::string& key, long lo, long hi) const {
  YAML::Node value = required(key);
  long v = 0;
  const std::string allowed = "allowed integer range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!value.IsScalar()) failValue(key, value, "must be an integer; " + allowed);
  try {
    v = value.as<long>();
  } catch (const YAML::Exception&) {
    failValue(key, value, "must be an integer; " + allowed);
  }
  if (v < lo || v > hi) failValue(key, value, "out of range; " + allowed);
  return v;
}

long ConfigNode::integer(const std::string& key, long lo, long hi, long default_value) const {
  return has(key) ? integer(key, lo, hi) : default_value;
}

bool ConfigNode::flag(const std::string& key) const {
  YAML::Node value = required(key);
  try {
    if (value.IsScalar()) return value.as<bool>();
  } catch (const YAML::Exception&) {
  }
  failValue(key, value, "must be true or false");
}

bool ConfigNode::flag(const std::string& key, bool default_value) const { return has(key) ? flag(key) : default_value; }

std::string ConfigNode::choice(const std::string& key, const std::vector<std::string>& allowed) const {
  const std::string v = text(key);
  for (const auto& a : allowed) {
    if (a == v) return v;
  }
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  failValue(key, node_[key], "unknown value; allowed: " + list);
}

std::string ConfigNode::choice(const std::string& key, const std::vector<std::string>& allowed,
                               const std::string& default_value) const {
  return has(key) ? choice(key, allowed) : default_value;
}

std::string ConfigNode::text(const std::string& key) const {
  YAML::Node value = required(key);
  if (!value.IsScalar()) failValue(key, value, "must be a string");
  const std::string v = value.as<std::string>();
  if (v.empty()) failValue(key, value, "must not be empty");
  return v;
}

std::string ConfigNode::text(const std::string& key, const std::string& default_value) const {
  return has(key) ? text(key) : default_value;
}

std::vector<double> ConfigNode::numbers(const std::string& key, const Range& range, size_t min_count,
                                        size_t max_count) const {
  YAML::Node value = required(key);
  if (!value.IsSequence()) failValue(key, value, "must be a list of numbers");
  if (value.size() < min_count || value.size() > max_count) {
    failValue(key, value,
              "must have between " + std::to_string(min_count) + " and " +
                  (max_count == std::numeric_limits<size_t>::max() ? std::string("any number of")
                                                                   : std::to_string(max_count)) +
                  " entries");
  }
  std::vector<double> out;
  for (const auto& item : value) {
    double v = 0.0;
    try {
      v = item.as<double>();
    } catch (const YAML::Exception&) {
      failValue(key, value, "entry " + describeValue(item) + " is not a number");
    }
    if (!std::isfinite(v) || !range.contains(v)) {
      failValue(key, value, "entry " + describeValue(item) + " out of range; allowed range " + range.describe());
    }
    out.push_back(v);
  }
  return out;
}

std::vector<std::string> ConfigNode::texts(const std::string& key) const {
  YAML::Node value = required(key);
  if (!value.IsSequence()) failValue(key, value, "must be a list of strings");
  std::vector<std::string> out;
  for (const auto& item : value) {
    if (!item.IsScalar()) failValue(key, value, "entries must be strings");
    out.push_back(item.as<std::string>());
  }
  return out;
}

std::string ConfigNode::filePath(const std::string& key) const {
  const fs::path p = text(key);
  if (p.is_absolute()) return p.string();
  const std::string source = fileOf(key);
  if (source.rfind("command-line", 0) == 0) return fs::absolute(p).string();
  return (fs::path(source).parent_path() / p).lexically_normal().string();
}

Config Config::load(const std::string& file, const std::vector<std::string>& overrides) {
  auto data = std::make_shared<detail::ConfigData>();
  std::vector<fs::path> stack;
  data->root = loadFileRecursive(file, data->sources, stack);
  data->file = fs::weakly_canonical(file).string();
  for (const auto& o : overrides) applyOverride(*data, o);
  return Config(data);
}

Config Config::fromString(const std::string& yaml_text, const std::string& label) {
  auto data = std::make_shared<detail::ConfigData>();
  try {
    data->root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ConfigError("config error in " + label + ": not valid YAML: " + e.what());
  }
  if (data->root.IsNull()) data->root = YAML::Node(YAML::NodeType::Map);
  if (!data->root.IsMap()) throw ConfigError("config error in " + label + ": top level must be a map");
  data->file = label;
  recordSources(data->root, "", label, data->sources);
  return Config(data);
}

ConfigNode Config::root() const { return ConfigNode(data_, data_->root, ""); }

std::string Config::dump() const {
  YAML::Emitter out;
  out << data_->root;
  return out.c_str();
}

const std::string& Config::file() const { return data_->file; }

}  // namespace railvib
