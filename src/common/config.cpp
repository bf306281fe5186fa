#include "railvib/common/config.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "railvib/common/plausibility.hpp"

namespace fs = std::filesystem;

namespace railvib {

namespace detail {
struct ConfigData {
  YAML::Node root;
  std::string file;
  // leaf or section key path -> file that set it
  std::map<std::string, std::string> sources;
  // Key paths the loaders asked for (list indices as "[]"), and the subtrees of inactive
  // alternatives (siblings named after a choice's other values): refuseUnknownKeys() knows both.
  mutable std::set<std::string> queried;
  mutable std::set<std::string> inactive;
  // plausibility.accept: key paths whose value may lie outside its quantity's typical range
  std::set<std::string> plausibility_accept;
  // What a reader of the resolved configuration should know (config-check prints them).
  std::vector<std::string> notes;
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

// "soil.layers[3].thickness_m" -> "soil.layers[].thickness_m": one key for every entry of a list.

std::string parentOf(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? std::string() : path.substr(0, dot);
}

std::string lastKeyOf(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// One pass over the parse events of one YAML text that checks them and builds the node tree (as
// yaml-cpp's own YAML::Load builds it: tags, styles; but each alias is a copy of its anchor's value,
// not the same node, so that an override of one key path never changes another): no repeated key in
// a map, keys are plain scalars, bounded nesting, and bounded aliases (an alias of an anchor holding
// aliases, no deeper; bounded size once expanded; never an alias inside the value its anchor names,
// a value that would contain itself), so an alias bomb or a cycle is refused before it is expanded.
// The first refusal waits for the document's end: a syntax error the parser finds later in the text
// is said first (what is wrong with the text before what is wrong with its values).
class StrictYamlReader : public YAML::EventHandler {
 public:
  explicit StrictYamlReader(std::string label) : label_(std::move(label)) {}

  // The document's root (a null node for an empty text).
  const YAML::Node& root() const { return root_; }

  void OnDocumentStart(const YAML::Mark&) override {
    if (++documents_ > 1) throw ConfigError("config error in " + label_ + ": more than one YAML document");
  }
  void OnDocumentEnd() override {
    if (refusal_) throw *refusal_;
  }
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    checked([&] { leaf(mark, anchor, "~", YAML::Node(YAML::NodeType::Null)); });
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    checked([&] {
      YAML::Node node(value);
      node.SetTag(tag);
      leaf(mark, anchor, value, node);
    });
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    checked([&] { alias(mark, anchor); });
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value style) override {
    checked([&] { open(mark, tag, anchor, false, style); });
  }
  void OnSequenceEnd() override {
    checked([&] { close(); });
  }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value style) override {
    checked([&] { open(mark, tag, anchor, true, style); });
  }
  void OnMapEnd() override {
    checked([&] { close(); });
  }

 private:
  // An event is read while nothing was refused; after a refusal the parser runs on for its syntax
  // errors only (nothing is built, so an alias bomb stays unexpanded).
  template <class Read>
  void checked(Read&& read) {
    if (refusal_) return;
    try {
      read();
    } catch (const ConfigError& e) {
      refusal_.emplace(e);
    }
  }
  void alias(const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (!stack_.empty() && stack_.back().is_map && stack_.back().expect_key) {
      fail(mark, "an alias cannot be a key");
    }
    for (const Frame& open_frame : stack_) {
      if (open_frame.anchor == anchor) {
        fail(mark, "an alias inside the value its anchor names (a value that would contain itself)");
      }
    }
    const auto it = anchors_.find(anchor);
    if (it == anchors_.end()) fail(mark, "an alias of no anchor");
    const int depth = it->second.alias_depth + 1;
    if (depth > kMaxAliasDepth) {
      fail(mark, "aliases nested " + std::to_string(depth) + " deep (an anchor that holds aliases of anchors " +
                     "that hold aliases...); at most " + std::to_string(kMaxAliasDepth) + " allowed");
    }
    add(mark, it->second.size, depth);  // (refuses before the copy when the expansion is too large)
    // A copy (YAML::Clone): the tree shares no node, since every alias before this one is a copy too.
    attach(YAML::Clone(it->second.node));
  }

  struct Frame {
    bool is_map = false;
    bool expect_key = true;
    std::map<std::string, int> keys;  // key -> line
    std::string path;
    std::string pending_key;
    YAML::Node pending_key_node;
    YAML::Node node;  // the map or list being built
    YAML::anchor_t anchor = 0;
    size_t size = 1;
    int alias_depth = 0;
  };
  struct Anchor {
    YAML::Node node;
    size_t size = 1;
    int alias_depth = 0;
  };

  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& reason) const {
    throw ConfigError("config error in " + label_ + ":" + std::to_string(mark.line + 1) + ": " + reason);
  }
  std::string childPath() const {
    if (stack_.empty()) return "";
    const Frame& f = stack_.back();
    return f.is_map ? joinPath(f.path, f.pending_key) : f.path + "[]";
  }
  void add(const YAML::Mark& mark, size_t nodes, int alias_depth) {
    total_ += nodes;
    if (total_ > kMaxExpandedNodes) {
      fail(mark, "more than " + std::to_string(kMaxExpandedNodes) + " values once its aliases are expanded");
    }
    if (!stack_.empty()) {
      stack_.back().size += nodes;
      stack_.back().alias_depth = std::max(stack_.back().alias_depth, alias_depth);
    }
  }
  // A finished value (scalar, alias or collection) goes into the map or list around it, or is the root;
  // the next scalar of a map is a key again.
  void attach(const YAML::Node& value) {
    if (stack_.empty()) {
      root_.reset(value);
      return;
    }
    Frame& f = stack_.back();
    if (f.is_map) {
      f.node.force_insert(f.pending_key_node, value);
      f.expect_key = true;
    } else {
      f.node.push_back(value);
    }
  }
  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string& value, const YAML::Node& node) {
    if (anchor) remember(anchor, Anchor{node, 1, 0});
    if (!stack_.empty() && stack_.back().is_map && stack_.back().expect_key) {
      Frame& f = stack_.back();
      const auto [it, inserted] = f.keys.emplace(value, mark.line + 1);
      if (!inserted) {
        fail(mark, "duplicate key '" + joinPath(f.path, value) + "' (first set at line " + std::to_string(it->second) +
                       "); a repeated key would silently keep one of the values");
      }
      f.pending_key = value;
      // reset, not =: assigning to a yaml-cpp node that holds one would rewrite the node it holds
      // (the previous key, already in the map).
      f.pending_key_node.reset(node);
      f.expect_key = false;
      add(mark, 1, 0);
      return;
    }
    add(mark, 1, 0);
    attach(node);
  }
  void remember(YAML::anchor_t anchor, Anchor value) {
    anchors_.erase(anchor);  // (never assigned over: see pending_key_node)
    anchors_.emplace(anchor, std::move(value));
  }
  void open(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor, bool is_map,
            YAML::EmitterStyle::value style) {
    if (!stack_.empty() && stack_.back().is_map && stack_.back().expect_key) {
      fail(mark, "a key must be a plain name, not a " + std::string(is_map ? "map" : "list"));
    }
    if (static_cast<int>(stack_.size()) >= kMaxConfigNesting) {
      fail(mark, "nested deeper than " + std::to_string(kMaxConfigNesting) + " levels");
    }
    Frame f;
    f.is_map = is_map;
    f.path = childPath();
    f.anchor = anchor;
    f.node.reset(YAML::Node(is_map ? YAML::NodeType::Map : YAML::NodeType::Sequence));
    f.node.SetTag(tag);
    f.node.SetStyle(style);
    stack_.push_back(std::move(f));
  }
  void close() {
    Frame f = std::move(stack_.back());
    stack_.pop_back();
    if (f.anchor) remember(f.anchor, Anchor{f.node, f.size, f.alias_depth});
    // The nodes inside were already counted in total_; the parent's subtree grows by them.
    if (!stack_.empty()) {
      stack_.back().size += f.size;
      stack_.back().alias_depth = std::max(stack_.back().alias_depth, f.alias_depth);
    }
    attach(f.node);
  }

  std::string label_;
  std::vector<Frame> stack_;
  std::map<YAML::anchor_t, Anchor> anchors_;
  YAML::Node root_;
  std::optional<ConfigError> refusal_;
  size_t total_ = 0;
  int documents_ = 0;
};

// Parse one YAML text, checked while it is read (StrictYamlReader); `label` names it in errors.
YAML::Node parseStrict(const std::string& text, const std::string& label) {
  if (text.size() > kMaxConfigBytes) {
    throw ConfigError("config error in " + label + ": " + std::to_string(text.size()) + " bytes, more than the " +
                      std::to_string(kMaxConfigBytes) + " a configuration may have");
  }
  try {
    // One parse: yaml-cpp's parser for the syntax, the reader for the checks and the tree.
    std::istringstream in(text);
    YAML::Parser parser(in);
    StrictYamlReader reader(label);
    while (parser.HandleNextDocument(reader)) {
    }
    return reader.root();
  } catch (const YAML::Exception& e) {
    throw ConfigError("config error in " + label + ": not valid YAML: " + e.what());
  }
}

// The text of a config file: a regular, readable file of bounded size.
std::string readConfigText(const fs::path& file) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec || !fs::exists(st)) throw ConfigError("config error: file not found: " + file.string());
  if (fs::is_directory(st)) throw ConfigError("config error: " + file.string() + " is a directory, not a config file");
  if (!fs::is_regular_file(st)) throw ConfigError("config error: " + file.string() + " is not a regular file");
  const auto size = fs::file_size(file, ec);
  if (!ec && size > kMaxConfigBytes) {
    throw ConfigError("config error in " + file.string() + ": " + std::to_string(size) + " bytes, more than the " +
                      std::to_string(kMaxConfigBytes) + " a configuration may have");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError("config error: cannot read " + file.string() + ": " + std::strerror(errno));
  std::string text;
  text.resize(kMaxConfigBytes + 1);
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));
  if (in.bad()) throw ConfigError("config error: cannot read " + file.string());
  return text;
}

// Record the source file of every node below `node`.
void recordSources(const YAML::Node& node, const std::string& path, const std::string& file,
                   std::map<std::string, std::string>& sources) {
  if (!path.empty()) sources[path] = file;
  if (node.IsMap()) {
    for (const auto& kv : node) {
      const std::string key = kv.first.as<std::string>();
      // A key path in one key ("soil.mesh.f_max_hz: 30") would be a key of its own that no loader asks
      // for: say how it is written instead of calling it unknown.
      if (key.find('.') != std::string::npos) {
        throw ConfigError("config error in " + file + ": key '" + joinPath(path, key) +
                          "' holds dots: in a file a key path is nested (soil:, mesh:, f_max_hz: on lines of "
                          "their own, indented), on the command line it is --set " +
                          joinPath(path, key) + "=VALUE");
      }
      recordSources(kv.second, joinPath(path, key), file, sources);
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

// Include chains are bounded (a scenario's are 2 deep and 7 files) and each file is read once: a file
// included a second time would re-impose its values over those merged in between, an order nobody means.
constexpr size_t kMaxIncludeDepth = 8;
constexpr size_t kMaxIncludedFiles = 64;

struct IncludeState {
  std::vector<fs::path> stack;               // the chain being read
  std::map<fs::path, fs::path> included_by;  // every file read so far, and the file that included it
};

YAML::Node loadFileRecursive(const fs::path& file, const fs::path& includer,
                             std::map<std::string, std::string>& sources, IncludeState& state) {
  std::vector<fs::path>& stack = state.stack;
  const fs::path canonical = fs::weakly_canonical(file);
  for (const auto& open : stack) {
    if (open == canonical) {
      throw ConfigError("config error: include cycle through " + canonical.string());
    }
  }
  if (const auto seen = state.included_by.find(canonical); seen != state.included_by.end()) {
    throw ConfigError("config error in " + includer.string() + ": include " + canonical.string() +
                      ": already included (by " + seen->second.string() +
                      "); a file is included once, or its values would override those merged in between");
  }
  if (stack.size() >= kMaxIncludeDepth) {
    throw ConfigError("config error in " + includer.string() + ": include " + canonical.string() + ": more than " +
                      std::to_string(kMaxIncludeDepth) + " files deep");
  }
  if (state.included_by.size() >= kMaxIncludedFiles) {
    throw ConfigError("config error in " + includer.string() + ": include " + canonical.string() + ": more than " +
                      std::to_string(kMaxIncludedFiles) + " files in one configuration");
  }
  state.included_by[canonical] = includer.empty() ? fs::path("the command line") : includer;
  YAML::Node doc = parseStrict(readConfigText(canonical), canonical.string());
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
      if (!inc.IsScalar() || inc.Scalar().empty()) {
        throw ConfigError("config error in " + canonical.string() + ": include entry " + describeValue(inc) +
                          ": must be a file name");
      }
      const fs::path inc_path = canonical.parent_path() / inc.Scalar();
      merged = deepMerge(merged, loadFileRecursive(inc_path, canonical, sources, state));
    }
    doc.remove("include");
  }
  recordSources(doc, "", canonical.string(), sources);
  merged = deepMerge(merged, doc);
  stack.pop_back();
  return merged;
}

// One step of an override's key path: a key, or an index into the list before it
// ("layers[2].thickness_m": layers, [2], thickness_m).
struct OverrideStep {
  std::string key;  // empty for an index
  size_t index = 0;
};

// The key path up to and including `step`, written as the error messages write it.
std::string stepPath(const std::string& done, const OverrideStep& step) {
  return step.key.empty() ? done + "[" + std::to_string(step.index) + "]" : joinPath(done, step.key);
}

std::vector<OverrideStep> parseOverridePath(const std::string& path, const std::string& assignment) {
  const auto refuse = [&](const std::string& why) {
    throw ConfigError("config error: override '" + assignment + "': " + why +
                      " (a key path is key.key[INDEX].key, the index counting list entries from 0)");
  };
  std::vector<OverrideStep> steps;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) {
    if (part.empty()) refuse("empty key in path");
    const auto bracket = part.find('[');
    const std::string key = part.substr(0, bracket);
    if (key.empty()) refuse("'" + part + "' has no key before its index");
    if (key.find(']') != std::string::npos) refuse("'" + part + "' closes an index it did not open");
    steps.push_back({key, 0});
    for (size_t at = bracket; at != std::string::npos;) {
      const auto close = part.find(']', at);
      if (close == std::string::npos) refuse("'" + part + "' opens an index without closing it");
      const std::string digits = part.substr(at + 1, close - at - 1);
      if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos) {
        refuse("index '" + digits + "' in '" + part + "' is not a list position (0, 1, 2, ...)");
      }
      steps.push_back({"", std::stoul(digits)});
      at = close + 1;
      if (at == part.size()) break;
      if (part[at] != '[') refuse("'" + part + "' has text after its index");
    }
  }
  if (path.empty() || path.back() == '.') refuse("empty key in path");
  return steps;
}

// `base` with `value` merged in at the path steps[from..] (maps along the path are created; a list entry
// named by an index must exist, so that an override cannot create holes in a list). `replaced` is set to
// what the path held before.
YAML::Node setAtPath(const YAML::Node& base, const std::vector<OverrideStep>& steps, size_t from,
                     const YAML::Node& value, const std::string& done, const std::string& assignment,
                     YAML::Node& replaced) {
  if (from == steps.size()) {
    replaced = base;
    return deepMerge(base, value);
  }
  const OverrideStep& step = steps[from];
  const std::string path = stepPath(done, step);
  if (!step.key.empty()) {
    YAML::Node result = base.IsMap() ? YAML::Clone(base) : YAML::Node(YAML::NodeType::Map);
    // (a missing key of a const map is an invalid node, which no type query may see)
    const YAML::Node child = base.IsMap() && base[step.key] ? base[step.key] : YAML::Node(YAML::NodeType::Undefined);
    result[step.key] = setAtPath(child, steps, from + 1, value, path, assignment, replaced);
    return result;
  }
  if (!base.IsDefined() || !base.IsSequence()) {
    throw ConfigError("config error: override '" + assignment + "': " + done + " is " +
                      (base.IsDefined() ? "not a list" : "not set") + ", so it has no entry [" +
                      std::to_string(step.index) + "]");
  }
  if (step.index >= base.size()) {
    throw ConfigError("config error: override '" + assignment + "': " + done + " has " + std::to_string(base.size()) +
                      " entries (indices 0 to " + std::to_string(base.size() - 1) + "), no [" +
                      std::to_string(step.index) + "]; to change the list, set " + done + "=[...]");
  }
  YAML::Node copy = YAML::Clone(base);
  copy[step.index] = setAtPath(base[step.index], steps, from + 1, value, path, assignment, replaced);
  return copy;
}

void applyOverride(detail::ConfigData& data, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ConfigError("config error: override '" + assignment + "' must look like key.path=value");
  }
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = parseStrict(assignment.substr(eq + 1), "override '" + assignment + "'");
  } catch (const ConfigError& e) {
    throw ConfigError(std::string(e.what()) + " (the value of an override is parsed as YAML)");
  }
  const std::vector<OverrideStep> steps = parseOverridePath(path, assignment);
  YAML::Node existing;
  data.root = setAtPath(data.root, steps, 0, value, "", assignment, existing);
  // A list replaced by a shorter one drops entries the files had: say which (by name when they have one).
  if (existing.IsDefined() && existing.IsSequence() && value.IsSequence() && value.size() < existing.size()) {
    std::set<std::string> kept;
    for (const auto& entry : value) {
      if (entry.IsMap() && entry["name"] && entry["name"].IsScalar()) kept.insert(entry["name"].Scalar());
    }
    std::string dropped;
    for (size_t i = 0; i < existing.size(); ++i) {
      const YAML::Node entry = existing[i];
      const bool named = entry.IsMap() && entry["name"] && entry["name"].IsScalar();
      if (named && kept.count(entry["name"].Scalar())) continue;
      if (!named && i < value.size()) continue;
      dropped += (dropped.empty() ? "" : ", ") + (named ? entry["name"].Scalar() : "[" + std::to_string(i) + "]");
    }
    data.notes.push_back("override '" + path + "=...' replaces a list of " + std::to_string(existing.size()) +
                         " entries by " + std::to_string(value.size()) +
                         (dropped.empty() ? "" : "; dropped: " + dropped));
  }
  const std::string label = "command-line override '" + assignment + "'";
  // The override is the source of its path and of every key on the way to it (as a file is of its keys).
  std::string step_path;
  for (const auto& step : steps) {
    step_path = stepPath(step_path, step);
    data.sources[step_path] = label;
  }
  recordSources(value, step_path, label, data.sources);
}

}  // namespace

namespace {
std::string magnitudeReason() {
  std::ostringstream s;
  s << "beyond the magnitude of any value of a railvib scenario (|value| <= " << kMaxConfigMagnitude << " in SI units)";
  return s.str();
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

void ConfigNode::record(const std::string& key) const { data_->queried.insert(normalizedKeyPath(childPath(key))); }

void ConfigNode::markKnown(const std::string& key) const { data_->inactive.insert(normalizedKeyPath(childPath(key))); }

bool ConfigNode::has(const std::string& key) const {
  record(key);
  return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
}

YAML::Node ConfigNode::required(const std::string& key) const {
  if (!has(key)) {
    // A present key a few letters away is most likely the intended one, misspelt.
    // Ties (x_min_mm and y_min_m are both one edit from x_min_m) go to the longer common prefix:
    // a slip is more often at the end of a name than at its start.
    std::string near;
    size_t best = std::string::npos, best_prefix = 0;
    if (node_.IsMap()) {
      for (const auto& kv : node_) {
        const std::string k = kv.first.as<std::string>();
        const size_t d = editDistance(k, key);
        size_t prefix = 0;
        while (prefix < k.size() && prefix < key.size() && k[prefix] == key[prefix]) ++prefix;
        if (k != key && d <= std::max<size_t>(2, key.size() / 3) && (d < best || (d == best && prefix > best_prefix))) {
          best = d;
          best_prefix = prefix;
          near = k;
        }
      }
    }
    failValue(key, YAML::Node(),
              near.empty() ? "required key is missing"
                           : "required key is missing (is '" + childPath(near) + "' a misspelling of it?)");
  }
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

namespace {
// A number written as text (quoted, "8.0e6", or tagged !!str) is refused: yaml-cpp would convert it,
// other YAML readers (the scripts', PyYAML) keep it a string, and a quote is usually a slip.
bool writtenAsText(const YAML::Node& value) {
  return value.IsScalar() && (value.Tag() == "!" || value.Tag() == "tag:yaml.org,2002:str");
}
const char* const kNumberAsText = "is text (in quotes or tagged !!str), not a number: write the number without quotes";
}  // namespace

double ConfigNode::number(const std::string& key, const Range& range) const {
  YAML::Node value = required(key);
  double v = 0.0;
  if (!value.IsScalar()) failValue(key, value, "must be a number");
  if (writtenAsText(value)) failValue(key, value, kNumberAsText);
  try {
    v = value.as<double>();
  } catch (const YAML::Exception&) {
    failValue(key, value, "must be a number");
  }
  if (!std::isfinite(v)) failValue(key, value, "must be a finite number; allowed range " + range.describe());
  if (!range.contains(v)) failValue(key, value, "out of range; allowed range " + range.describe());
  if (std::abs(v) > kMaxConfigMagnitude) failValue(key, value, magnitudeReason());
  const std::string path = childPath(key);
  if (const PlausibilityRule* rule = plausibilityRuleFor(path);
      rule && !isTypical(*rule, v) && !data_->plausibility_accept.count(path)) {
    std::ostringstream reason;
    reason << "outside the typical range of this quantity, " << rule->typical_lo << " to " << rule->typical_hi << " "
           << rule->unit << " in magnitude (" << rule->slip << "); if the value is meant, list '" << path
           << "' under plausibility.accept";
    failValue(key, value, reason.str());
  }
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
  if (writtenAsText(value)) failValue(key, value, kNumberAsText);
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
    if (a != v) continue;
    // Sibling sections named after the other allowed values are the alternatives not chosen.
    for (const auto& other : allowed) {
      if (other != v && node_.IsMap() && node_[other].IsDefined() && node_[other].IsMap()) markKnown(other);
    }
    return v;
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
    if (writtenAsText(item)) failValue(key, value, "entry " + describeValue(item) + " " + kNumberAsText);
    try {
      v = item.as<double>();
    } catch (const YAML::Exception&) {
      failValue(key, value, "entry " + describeValue(item) + " is not a number");
    }
    if (!std::isfinite(v) || !range.contains(v)) {
      failValue(key, value, "entry " + describeValue(item) + " out of range; allowed range " + range.describe());
    }
    if (std::abs(v) > kMaxConfigMagnitude)
      failValue(key, value, "entry " + describeValue(item) + ": " + magnitudeReason());
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

namespace {
// plausibility.accept: a list of key paths (as config errors name them, with list indices).
void readPlausibilityAccept(detail::ConfigData& data) {
  const YAML::Node section = data.root["plausibility"];
  if (!section.IsDefined() || section.IsNull()) return;
  const std::string file = data.sources.count("plausibility") ? data.sources.at("plausibility") : data.file;
  const std::string where = " [file " + file + "]";
  if (!section.IsMap())
    throw ConfigError("config error: plausibility = " + describeValue(section) +
                      ": must be a map (accept: [KEY PATHS])" + where);
  for (const auto& kv : section) {
    if (kv.first.as<std::string>() != "accept") {
      throw ConfigError("config error: plausibility." + kv.first.as<std::string>() +
                        ": unknown key (plausibility has accept only)" + where);
    }
  }
  const YAML::Node accept = section["accept"];
  if (!accept.IsSequence()) {
    throw ConfigError("config error: plausibility.accept = " + describeValue(accept) + ": must be a list of key paths" +
                      where);
  }
  for (const auto& entry : accept) {
    if (!entry.IsScalar() || entry.Scalar().empty()) {
      throw ConfigError("config error: plausibility.accept entry " + describeValue(entry) +
                        ": must be a key path such as soil.layers[0].density_kg_m3" + where);
    }
    data.plausibility_accept.insert(entry.Scalar());
  }
  data.queried.insert("plausibility");
  data.queried.insert("plausibility.accept");
}
}  // namespace

Config Config::load(const std::string& file, const std::vector<std::string>& overrides) {
  auto data = std::make_shared<detail::ConfigData>();
  IncludeState includes;
  data->root = loadFileRecursive(file, fs::path(), data->sources, includes);
  data->file = fs::weakly_canonical(file).string();
  for (const auto& o : overrides) applyOverride(*data, o);
  readPlausibilityAccept(*data);
  return Config(data);
}

Config Config::fromString(const std::string& yaml_text, const std::string& label) {
  auto data = std::make_shared<detail::ConfigData>();
  data->root = parseStrict(yaml_text, label);
  if (data->root.IsNull()) data->root = YAML::Node(YAML::NodeType::Map);
  if (!data->root.IsMap()) throw ConfigError("config error in " + label + ": top level must be a map");
  data->file = label;
  recordSources(data->root, "", label, data->sources);
  readPlausibilityAccept(*data);
  return Config(data);
}

ConfigNode Config::root() const { return ConfigNode(data_, data_->root, ""); }

const std::vector<std::string>& Config::notes() const { return data_->notes; }

std::string Config::dump() const {
  YAML::Emitter out;
  out << data_->root;
  return out.c_str();
}

const std::string& Config::file() const { return data_->file; }

namespace {

struct UnknownKeyWalk {
  const detail::ConfigData& data;
  std::vector<std::string>& lines;

  bool known(const std::string& normalized) const {
    if (data.queried.count(normalized)) return true;
    // Inside an inactive alternative (or a subtree marked known) that no loader read into: a
    // subtree a loader validates anyway (soil.boundary keeps the sections of the methods it does
    // not choose) is checked key by key, so a typo there is refused as anywhere else.
    for (std::string p = normalized; !p.empty(); p = parentOf(p)) {
      if (data.inactive.count(p)) return !readInside(p);
    }
    return false;
  }

  // Whether a loader asked for a key below `path`.
  bool readInside(const std::string& path) const {
    const std::string prefix = path + ".";
    const auto it = data.queried.lower_bound(prefix);
    return it != data.queried.end() && it->compare(0, prefix.size(), prefix) == 0;
  }

  // The valid keys next to `normalized`: what the loaders asked for under the same parent.
  std::vector<std::string> siblings(const std::string& normalized) const {
    const std::string parent = parentOf(normalized);
    std::vector<std::string> out;
    for (const std::set<std::string>* set : {&data.queried, &data.inactive}) {
      for (const auto& q : *set) {
        if (parentOf(q) == parent && (!parent.empty() || q.find('.') == std::string::npos)) {
          out.push_back(lastKeyOf(q));
        }
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  std::string sourceOf(std::string path) const {
    for (; !path.empty(); path = parentOf(path)) {
      const auto it = data.sources.find(path);
      if (it != data.sources.end()) return it->second;
    }
    return data.file;
  }

  std::string hint(const std::string& path) const {
    const std::string normalized = normalizedKeyPath(path);
    const std::string key = lastKeyOf(normalized);
    const std::vector<std::string> valid = siblings(normalized);
    if (valid.empty()) return "no key is read here";
    std::string best;
    size_t best_distance = std::string::npos;
    for (const auto& v : valid) {
      const size_t d = editDistance(key, v);
      if (d < best_distance) {
        best_distance = d;
        best = v;
      }
    }
    const std::string prefix = parentOf(path).empty() ? "" : parentOf(path) + ".";
    if (best_distance <= std::max<size_t>(2, key.size() / 3)) return "did you mean " + prefix + best + "?";
    std::string list;
    for (const auto& v : valid) list += (list.empty() ? "" : ", ") + v;
    return "valid keys here: " + list;
  }

  void walk(const YAML::Node& node, const std::string& path) {
    if (node.IsMap()) {
      for (const auto& kv : node) {
        const std::string child = joinPath(path, kv.first.as<std::string>());
        if (!known(normalizedKeyPath(child))) {
          lines.push_back("config error: " + child + " = " + describeValue(kv.second) + ": unknown key, " +
                          hint(child) + " [file " + sourceOf(child) + "]");
          continue;
        }
        walk(kv.second, child);
      }
    } else if (node.IsSequence()) {
      for (size_t i = 0; i < node.size(); ++i) walk(node[i], path + "[" + std::to_string(i) + "]");
    }
  }
};

}  // namespace

std::vector<std::string> Config::unknownKeys() const {
  std::vector<std::string> lines;
  UnknownKeyWalk{*data_, lines}.walk(data_->root, "");
  return lines;
}

void Config::refuseUnknownKeys() const {
  const std::vector<std::string> lines = unknownKeys();
  if (lines.empty()) return;
  std::string message;
  for (const auto& l : lines) message += (message.empty() ? "" : "\n") + l;
  throw ConfigError(message);
}

}  // namespace railvib
